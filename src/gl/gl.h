#pragma once
// The one place that includes the generated loaders.
#include <glad/gl.h>
