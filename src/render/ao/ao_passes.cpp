#include "render/ao/ao_passes.h"
namespace rtgi {
void appendAoPasses(std::vector<std::unique_ptr<Pass>>&) {}
void appendNearFieldPasses(std::vector<std::unique_ptr<Pass>>&) {}
}  // namespace rtgi
