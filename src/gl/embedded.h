#pragma once
// Files embedded at build time (cmake/embed.cmake): GLSL under compute/ and
// built-in scene descriptions under scenes/, addressed by their path relative
// to the repository root.
#include <optional>
#include <string>
#include <string_view>

namespace rtgi {
struct EmbeddedFile {
    const char* path;
    const char* text;
};
extern const EmbeddedFile kEmbeddedFiles[];
extern const int kEmbeddedFileCount;

// Looks a file up; when RTGI_DATA_DIR is set, reads it from that directory
// first (live editing of shaders without a rebuild).
std::optional<std::string> readEmbeddedFile(std::string_view path);
}  // namespace rtgi
