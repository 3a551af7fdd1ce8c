// The tinygltf implementation, compiled once and without the project's
// warning flags (third-party code). stb_image's implementation comes from
// Debian's libstb (linked statically).
#define TINYGLTF_IMPLEMENTATION
#define TINYGLTF_NO_STB_IMAGE_WRITE
#define TINYGLTF_NO_INCLUDE_STB_IMAGE_WRITE
#include <tiny_gltf.h>
