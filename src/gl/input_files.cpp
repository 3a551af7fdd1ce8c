#include "gl/input_files.h"

#include <fcntl.h>
#include <sys/stat.h>
#include <sys/vfs.h>
#include <unistd.h>

#include <cerrno>
#include <cstring>

namespace rtgi {

namespace {

// statfs(2) magic numbers of the kernel's pseudo file systems: their files
// report size 0 (or 4096) and produce their text on read, without end for
// some; they are never scene or configuration input.
constexpr long kProcMagic = 0x9fa0, kSysfsMagic = 0x62656572, kDebugfsMagic = 0x64626720, kTracefsMagic = 0x74726163;

std::string kindProblem(const struct stat& st) {
    if (S_ISDIR(st.st_mode)) return "is a directory, not a file";
    if (S_ISFIFO(st.st_mode)) return "is a named pipe (FIFO), not a regular file";
    if (S_ISCHR(st.st_mode)) return "is a character device, not a regular file";
    if (S_ISBLK(st.st_mode)) return "is a block device, not a regular file";
    if (S_ISSOCK(st.st_mode)) return "is a socket, not a regular file";
    if (!S_ISREG(st.st_mode)) return "is not a regular file";
    return {};
}

std::string sizeProblem(std::uintmax_t size, InputKind kind) {
    if (size <= inputSizeLimit(kind)) return {};
    return "is " + std::to_string(size) + " bytes, more than " + inputLimitText(kind);
}

}  // namespace

std::uintmax_t inputSizeLimit(InputKind kind) {
    switch (kind) {
        case InputKind::Scene:
        case InputKind::SceneData: return std::uintmax_t(2000) << 20;  // tinygltf takes 32-bit sizes
        case InputKind::Image: return std::uintmax_t(4) << 30;         // a 16384^2 RGB float PFM is 3 GiB
        case InputKind::Config: return std::uintmax_t(16) << 20;
        case InputKind::Records: return std::uintmax_t(1) << 30;
    }
    return 0;
}

std::string inputLimitText(InputKind kind) {
    switch (kind) {
        case InputKind::Scene: return "the 2000 MiB limit for glTF files";
        case InputKind::SceneData: return "the 2000 MiB limit for glTF buffers and images";
        case InputKind::Image: return "the 4 GiB limit for image files";
        case InputKind::Config: return "the 16 MiB limit for configuration files";
        case InputKind::Records: return "the 1 GiB limit for sweep records";
    }
    return {};
}

std::string inputFileProblem(const std::string& path, InputKind kind) {
    if (path.empty()) return "the file name is empty";
    struct stat st {};
    if (::stat(path.c_str(), &st) != 0) {
        if (errno == ENOENT) return "does not exist";
        if (errno == ENOTDIR) return "does not exist (a part of the path is not a directory)";
        return std::string("cannot be examined (") + std::strerror(errno) + ")";
    }
    if (std::string k = kindProblem(st); !k.empty()) return k;
    struct statfs fsInfo {};
    if (::statfs(path.c_str(), &fsInfo) == 0) {
        const long magic = long(fsInfo.f_type);
        if (magic == kProcMagic || magic == kSysfsMagic || magic == kDebugfsMagic || magic == kTracefsMagic)
            return "is a kernel pseudo-file (/proc, /sys), not a regular file";
    }
    return sizeProblem(std::uintmax_t(st.st_size), kind);
}

bool readInputBytes(const std::string& path, InputKind kind, std::vector<unsigned char>& out, std::string& why) {
    out.clear();
    why = inputFileProblem(path, kind);
    if (!why.empty()) return false;
    // O_NONBLOCK: should a FIFO have replaced the file since stat(), opening
    // it does not wait for a writer (fstat below refuses it).
    const int fd = ::open(path.c_str(), O_RDONLY | O_NONBLOCK | O_CLOEXEC | O_NOCTTY);
    if (fd < 0) {
        why = std::string("cannot be opened (") + std::strerror(errno) + ")";
        return false;
    }
    struct stat st {};
    if (::fstat(fd, &st) != 0 || !(why = kindProblem(st)).empty() ||
        !(why = sizeProblem(std::uintmax_t(st.st_size), kind)).empty()) {
        if (why.empty()) why = std::string("cannot be examined (") + std::strerror(errno) + ")";
        ::close(fd);
        return false;
    }
    // Read to the end, but never past the limit (a file growing while it is
    // read stops there as well): the size fstat reported first, then 64 KiB
    // chunks until the end of the file.
    const std::uintmax_t limit = inputSizeLimit(kind);
    out.resize(std::size_t(st.st_size));
    std::size_t got = 0;
    unsigned char chunk[65536];
    for (;;) {
        const bool initial = got < out.size();
        const ssize_t n = initial ? ::read(fd, out.data() + got, out.size() - got) : ::read(fd, chunk, sizeof chunk);
        if (n < 0 && (errno == EINTR || errno == EAGAIN)) continue;
        if (n < 0) {
            why = std::string("could not be read (") + std::strerror(errno) + ")";
            ::close(fd);
            out.clear();
            return false;
        }
        if (n == 0) break;
        if (!initial) out.insert(out.end(), chunk, chunk + n);
        got += std::size_t(n);
        if (got > limit) break;
    }
    ::close(fd);
    if (got > limit) {
        why = "grew beyond " + inputLimitText(kind) + " while it was read";
        out.clear();
        return false;
    }
    out.resize(got);
    return true;
}

std::string readInputFile(const std::string& path, InputKind kind) {
    std::vector<unsigned char> bytes;
    std::string why;
    if (!readInputBytes(path, kind, bytes, why)) throw InputError(escapeControl(path) + ": " + why);
    return std::string(bytes.begin(), bytes.end());
}

std::string escapeControl(std::string_view s) {
    static const char* hex = "0123456789abcdef";
    std::string out;
    out.reserve(s.size());
    std::size_t i = 0;
    auto escapeByte = [&](unsigned char c) {
        if (c == '\n') out += "\\n";
        else if (c == '\t') out += "\\t";
        else if (c == '\r') out += "\\r";
        else {
            out += "\\x";
            out += hex[c >> 4];
            out += hex[c & 15];
        }
    };
    while (i < s.size()) {
        auto c = static_cast<unsigned char>(s[i]);
        std::size_t len = c < 0x80 ? 1 : (c >> 5) == 0x6 ? 2 : (c >> 4) == 0xE ? 3 : (c >> 3) == 0x1E ? 4 : 0;
        bool ok = len > 0 && i + len <= s.size() && (len > 1 || (c >= 0x20 && c != 0x7F));
        for (std::size_t k = 1; ok && k < len; ++k) ok = (static_cast<unsigned char>(s[i + k]) >> 6) == 0x2;
        if (ok && len == 2) ok = c >= 0xC2;  // no overlong forms
        if (ok && len == 2) {                 // C1 controls (U+0080..U+009F): CSI on some terminals
            const unsigned cp = ((c & 0x1Fu) << 6) | (static_cast<unsigned char>(s[i + 1]) & 0x3Fu);
            ok = cp >= 0xA0;
        }
        if (!ok) {
            escapeByte(c);
            ++i;
            continue;
        }
        out.append(s.substr(i, len));
        i += len;
    }
    return out;
}

}  // namespace rtgi
