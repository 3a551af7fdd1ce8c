#include "gl/output_files.h"

#include <cerrno>
#include <cstring>
#include <filesystem>
#include <string>

#include <fcntl.h>
#include <sys/stat.h>
#include <unistd.h>

namespace rtgi {

namespace {

namespace fs = std::filesystem;

std::string errnoText(int e) { return std::strerror(e); }

std::string parentOf(const std::string& path) {
    std::string parent = fs::path(path).parent_path().string();
    return parent.empty() ? std::string(".") : parent;
}

// write(2) until done; false with errno set on failure.
bool writeAll(int fd, std::string_view bytes) {
    std::size_t done = 0;
    while (done < bytes.size()) {
        ssize_t n = ::write(fd, bytes.data() + done, bytes.size() - done);
        if (n < 0) {
            if (errno == EINTR) continue;
            return false;
        }
        if (n == 0) {
            errno = EIO;
            return false;
        }
        done += std::size_t(n);
    }
    return true;
}

}  // namespace

void checkOutputTarget(const std::string& path) {
    struct stat st {};
    if (::lstat(path.c_str(), &st) != 0) {
        if (errno == ENOENT) return;
        throw OutputError(path + ": cannot be written (" + errnoText(errno) + ")");
    }
    if (S_ISLNK(st.st_mode))
        throw OutputError(path + ": is a symbolic link; result files are not written through links (remove it)");
    if (S_ISDIR(st.st_mode)) throw OutputError(path + ": is a directory, so the result file cannot be written");
}

void writeFileAtomic(const std::string& path, std::string_view bytes) {
    checkOutputTarget(path);
    // Temporary name in the same directory (rename works only within one
    // file system); mkstemp gives a fresh file that no link can point to.
    std::string tmpl = parentOf(path) + "/." + fs::path(path).filename().string() + ".tmp.XXXXXX";
    int fd = ::mkstemp(tmpl.data());
    if (fd < 0) throw OutputError(path + ": cannot be written (" + errnoText(errno) + ")");
    auto failWith = [&](int e) {
        ::close(fd);
        ::unlink(tmpl.c_str());
        throw OutputError(path + ": writing failed (" + errnoText(e) + ")");
    };
    ::fchmod(fd, 0644);  // mkstemp creates 0600; results are meant to be shared
    if (!writeAll(fd, bytes)) failWith(errno);
    if (::fsync(fd) != 0 && errno != EINVAL && errno != EROFS) failWith(errno);  // EINVAL: fs without fsync
    if (::close(fd) != 0) {
        int e = errno;
        ::unlink(tmpl.c_str());
        throw OutputError(path + ": writing failed (" + errnoText(e) + ")");
    }
    if (::rename(tmpl.c_str(), path.c_str()) != 0) {
        int e = errno;
        ::unlink(tmpl.c_str());
        throw OutputError(path + ": cannot be replaced (" + errnoText(e) + ")");
    }
}

void prepareOutputDirectory(const std::string& dir) {
    if (dir.empty()) throw OutputError("--out: the output directory is empty");
    std::error_code ec;
    fs::create_directories(dir, ec);
    if (ec) throw OutputError(dir + ": the output directory cannot be created (" + ec.message() + ")");
    if (!fs::is_directory(dir, ec)) throw OutputError(dir + ": the output path is not a directory");
    std::string probe = dir + "/.rtgi-write-probe.XXXXXX";
    int fd = ::mkstemp(probe.data());
    if (fd < 0) throw OutputError(dir + ": the output directory is not writable (" + errnoText(errno) + ")");
    ::close(fd);
    ::unlink(probe.c_str());
}

}  // namespace rtgi
