#pragma once
// In-framework ray-traced reference (SPEC 7).
#include "render/pass.h"

#include <memory>
#include <vector>

namespace rtgi {
void appendReferencePasses(std::vector<std::unique_ptr<Pass>>& frame);
}  // namespace rtgi
