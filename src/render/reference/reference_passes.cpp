#include "render/reference/reference_passes.h"
namespace rtgi {
void appendReferencePasses(std::vector<std::unique_ptr<Pass>>&) {}
}  // namespace rtgi
