#pragma once
// Build provenance (defined in the generated build/version.cpp; see
// cmake/version.cmake): the CMake project version and `git describe --tags
// --always --dirty` of the source tree at build time ("" outside a checkout).
namespace rtgi {
extern const char* const kProjectVersion;
extern const char* const kGitDescribe;
}  // namespace rtgi
