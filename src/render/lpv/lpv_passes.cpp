#include "render/lpv/lpv_passes.h"
namespace rtgi {
void appendLpvPasses(std::vector<std::unique_ptr<Pass>>&) {}
}  // namespace rtgi
