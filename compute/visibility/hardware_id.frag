// Hardware visibility buffer (baseline for the compute rasterizer's tests):
// the triangle id of the nearest fragment, drawn with raster/scene.vert.
#include "lib/raster_shared.h"
layout(location = RTGI_RASTER_ID_OUT) out uint outId;

void main() { outId = uint(gl_PrimitiveID); }
