#pragma once
// GPU resources with a size in the memory ledger. A Texture or Buffer registers
// its bytes when created and removes them when destroyed, so results.json can
// report per-resource memory for exactly what a frame allocated.
#include "gl/handles.h"

#include <cstdint>
#include <map>
#include <memory>
#include <stdexcept>
#include <string>

namespace rtgi::gl {

// glGetError reported GL_OUT_OF_MEMORY after an allocation (rtgi-bench exit 4).
class OutOfMemory : public std::runtime_error {
    using std::runtime_error::runtime_error;
};

class MemoryLedger {
public:
    void add(const std::string& name, std::int64_t bytes);
    void remove(const std::string& name, std::int64_t bytes);
    std::int64_t total() const;
    const std::map<std::string, std::int64_t>& entries() const { return entries_; }

private:
    std::map<std::string, std::int64_t> entries_;
};

// Registered bytes, released with the owner (move-only).
class LedgerEntry {
public:
    LedgerEntry() = default;
    LedgerEntry(MemoryLedger* ledger, std::string name, std::int64_t bytes);
    ~LedgerEntry();
    LedgerEntry(const LedgerEntry&) = delete;
    LedgerEntry& operator=(const LedgerEntry&) = delete;
    LedgerEntry(LedgerEntry&& o) noexcept;
    LedgerEntry& operator=(LedgerEntry&& o) noexcept;
    std::int64_t bytes() const { return bytes_; }

private:
    MemoryLedger* ledger_ = nullptr;
    std::string name_;
    std::int64_t bytes_ = 0;
};

// Bytes per texel of a sized internal format (0 for unknown formats).
int bytesPerTexel(GLenum internalFormat);

struct TextureDesc {
    GLenum target = GL_TEXTURE_2D;  // GL_TEXTURE_2D, GL_TEXTURE_3D, GL_TEXTURE_2D_ARRAY
    GLenum format = GL_RGBA16F;
    int width = 0, height = 0, depth = 1;
    int levels = 1;
    bool operator==(const TextureDesc&) const = default;
};

// RTGI_POISON=1 in the environment: new buffers start filled with 0xA5
// bytes instead of whatever the driver gives (tests of read-before-write).
bool poisonNewResources();

// Bytes of a texture's storage, every level (what the ledger registers).
std::int64_t textureBytes(const TextureDesc& desc);

// A texture by its ledger label and the descriptor it is allocated from.
struct NamedTextureDesc {
    std::string label;
    TextureDesc desc;
};

class Texture {
public:
    Texture() = default;
    Texture(MemoryLedger& ledger, std::string label, const TextureDesc& desc);
    GLuint id() const { return handle_.id(); }
    explicit operator bool() const { return bool(handle_); }
    const TextureDesc& desc() const { return desc_; }
    int width() const { return desc_.width; }
    int height() const { return desc_.height; }
    int depth() const { return desc_.depth; }
    GLenum format() const { return desc_.format; }
    const std::string& label() const { return label_; }
    // Sets min/mag filter and wrap mode (clamp to edge) on the texture itself;
    // only when they change: a texture parameter changed while earlier frames'
    // work still reads the texture may make the driver wait for that work (the
    // Cornell box's GPU-bound frame gapped 5-24 ms in the filters' scopes).
    void setSampling(GLenum minFilter, GLenum magFilter, GLenum wrap = GL_CLAMP_TO_EDGE) const;
    // Clears every level-0 texel to the given value (glClearTexImage).
    void clear(float r = 0, float g = 0, float b = 0, float a = 0) const;
    void clearInt(std::uint32_t v = 0) const;
    // Every level to zero (done once at creation).
    void zeroAllLevels() const;
    // Re-creates the texture only when the description changed (XeGTAO-style
    // ensureResources); returns true when it did. The label names a new
    // texture only: calling ensure with another label keeps the texture.
    bool ensure(MemoryLedger& ledger, const std::string& label, const TextureDesc& desc);
    void reset();

private:
    TextureHandle handle_;
    TextureDesc desc_;
    std::string label_;
    LedgerEntry entry_;
    mutable GLenum sampling_[3] = {0, 0, 0};  // min, mag, wrap last set (0: none)
};

class Buffer {
public:
    Buffer() = default;
    Buffer(MemoryLedger& ledger, std::string label, std::int64_t bytes, const void* data = nullptr,
           GLbitfield flags = GL_DYNAMIC_STORAGE_BIT);
    GLuint id() const { return handle_.id(); }
    explicit operator bool() const { return bool(handle_); }
    std::int64_t size() const { return size_; }
    void upload(const void* data, std::int64_t bytes, std::int64_t offset = 0) const;
    void download(void* data, std::int64_t bytes, std::int64_t offset = 0) const;
    void clearZero() const;
    bool ensure(MemoryLedger& ledger, const std::string& label, std::int64_t bytes);
    void reset();

private:
    BufferHandle handle_;
    std::int64_t size_ = 0;
    std::string label_;
    LedgerEntry entry_;
};

// Group count for n items in groups of `local` (the one place this is computed).
inline GLuint groupCount(int n, int local) { return GLuint((n + local - 1) / local); }

}  // namespace rtgi::gl
