#pragma once
// Result files written so that they are either complete or absent: every
// file goes to a temporary file in the same directory (same file system), is
// flushed to disk and renamed over the target (rename(2) is atomic), so a run
// killed mid-write leaves the previous file intact and a reader never sees a
// truncated results.json. Write errors (full disk, a directory in the way,
// unwritable directory) are errors, and nothing is written through a symbolic
// link: a link at the target path is refused, not followed.
#include <stdexcept>
#include <string>
#include <string_view>

namespace rtgi {

// A result file could not be written (rtgi-bench exit code 6).
class OutputError : public std::runtime_error {
    using std::runtime_error::runtime_error;
};

// Writes `bytes` to `path` atomically (temporary file + fsync + rename).
// Throws OutputError naming the path and the reason.
void writeFileAtomic(const std::string& path, std::string_view bytes);

// Creates `dir` (and its parents) when missing and proves that a file can be
// created in it (creates and removes a probe file). Throws OutputError naming
// the directory: call before the first frame so that an unwritable --out is
// found in milliseconds, not after the benchmark.
void prepareOutputDirectory(const std::string& dir);

// Throws OutputError when `path` exists and is a symbolic link or a
// directory (the checks writeFileAtomic makes before writing; for appenders).
void checkOutputTarget(const std::string& path);

}  // namespace rtgi
