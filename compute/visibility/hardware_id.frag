// Hardware visibility buffer (baseline for the compute rasterizer's tests):
// the triangle id of the nearest fragment, drawn with raster/scene.vert.
layout(location = 0) out uint outId;

void main() { outId = uint(gl_PrimitiveID); }
