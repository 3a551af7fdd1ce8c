#pragma once
// The one reader for every file the program reads: scenes (.gltf/.glb) and
// their buffers and images, --config, --sweep, --script, --compare images and
// masks, cached references, sweep records. Bad input must end in one sentence
// naming the file, never in a hang or an unbounded read, so before a file is
// opened its kind is taken from stat(2) (opening a FIFO for reading blocks
// until a writer comes; /dev/zero never ends), and reading stops at a size
// limit per kind (docs/STABILITY.md "Bad input"). The file is then opened with
// O_NONBLOCK and checked again with fstat(2), so a FIFO swapped in between the
// two calls cannot block either.
#include <cstdint>
#include <stdexcept>
#include <string>
#include <string_view>
#include <vector>

namespace rtgi {

// What a file is read as; each kind has its size limit (inputSizeLimit).
enum class InputKind {
    Scene,      // .gltf / .glb (tinygltf takes 32-bit sizes): 2000 MiB
    SceneData,  // a glTF's external buffer or image: 2000 MiB
    Image,      // --compare image, reference or mask (PNG, PFM, EXR); cached reference PFM: 4 GiB
    Config,     // --config, --sweep, --script, a cached reference's JSON: 16 MiB
    Records,    // a sweep's results.jsonl (resume): 1 GiB
};

std::uintmax_t inputSizeLimit(InputKind kind);
// "the 16 MiB limit for configuration files", for messages and --help.
std::string inputLimitText(InputKind kind);

// An input file that cannot be read: the message is one sentence that starts
// with the (escaped) path. Callers rethrow it as their own error class where
// the exit code differs (ConfigError for --config / --sweep).
class InputError : public std::runtime_error {
    using std::runtime_error::runtime_error;
};

// Why `path` cannot be read as a file of `kind`, from stat(2) alone (nothing
// is opened): "is a named pipe (FIFO), not a regular file", "does not exist",
// ... without the path; empty when it looks readable.
std::string inputFileProblem(const std::string& path, InputKind kind);

// Reads the whole file. Throws InputError "PATH: <problem>".
std::string readInputFile(const std::string& path, InputKind kind);
// The same for byte consumers (tinygltf, stb_image, tinyexr): returns false
// and sets `why` (the problem without the path) instead of throwing.
bool readInputBytes(const std::string& path, InputKind kind, std::vector<unsigned char>& out, std::string& why);

// `text` with control characters (newline, ESC, DEL, ...) and bytes that are
// not UTF-8 escaped as \n, \t, \r or \xNN, so that a file name or a string from
// a file prints as one inert line on a terminal and in JSON. Idempotent on its
// output (it contains no control characters).
std::string escapeControl(std::string_view text);

}  // namespace rtgi
