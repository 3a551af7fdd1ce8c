// The tinyexr implementation (Debian libtinyexr-dev's header), compiled once
// without the project's warning flags (third-party code); zlib does the ZIP
// compression (TINYEXR_USE_MINIZ is 0 in Debian's header).
#define TINYEXR_IMPLEMENTATION
#include <tinyexr.h>
