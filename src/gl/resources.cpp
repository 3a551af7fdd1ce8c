#include "gl/resources.h"

#include <cstdlib>
#include <stdexcept>
#include <utility>

namespace rtgi::gl {

void MemoryLedger::add(const std::string& name, std::int64_t bytes) { entries_[name] += bytes; }

void MemoryLedger::remove(const std::string& name, std::int64_t bytes) {
    auto it = entries_.find(name);
    if (it == entries_.end()) return;
    it->second -= bytes;
    if (it->second <= 0) entries_.erase(it);
}

std::int64_t MemoryLedger::total() const {
    std::int64_t t = 0;
    for (auto& [_, b] : entries_) t += b;
    return t;
}

LedgerEntry::LedgerEntry(MemoryLedger* ledger, std::string name, std::int64_t bytes)
    : ledger_(ledger), name_(std::move(name)), bytes_(bytes) {
    if (ledger_) ledger_->add(name_, bytes_);
}
LedgerEntry::~LedgerEntry() {
    if (ledger_) ledger_->remove(name_, bytes_);
}
LedgerEntry::LedgerEntry(LedgerEntry&& o) noexcept
    : ledger_(std::exchange(o.ledger_, nullptr)), name_(std::move(o.name_)), bytes_(std::exchange(o.bytes_, 0)) {}
LedgerEntry& LedgerEntry::operator=(LedgerEntry&& o) noexcept {
    if (this != &o) {
        if (ledger_) ledger_->remove(name_, bytes_);
        ledger_ = std::exchange(o.ledger_, nullptr);
        name_ = std::move(o.name_);
        bytes_ = std::exchange(o.bytes_, 0);
    }
    return *this;
}

int bytesPerTexel(GLenum f) {
    switch (f) {
        case GL_R8: case GL_R8UI: return 1;
        case GL_RG8: case GL_R16F: case GL_R16: case GL_R16UI: case GL_DEPTH_COMPONENT16: return 2;
        case GL_RGBA8: case GL_SRGB8_ALPHA8: case GL_R32F: case GL_R32UI: case GL_R32I: case GL_RG16F: case GL_RG16:
        case GL_R11F_G11F_B10F: case GL_RGB10_A2: case GL_DEPTH_COMPONENT32F: case GL_DEPTH24_STENCIL8:
        case GL_DEPTH_COMPONENT24: case GL_RGBA8UI: return 4;
        case GL_RGBA16F: case GL_RG32F: case GL_RGBA16: case GL_RG32UI: return 8;
        case GL_RGB32F: return 12;
        case GL_RGBA32F: case GL_RGBA32UI: return 16;
        default: return 0;
    }
}

std::int64_t textureBytes(const TextureDesc& d) {
    std::int64_t bytes = 0;
    for (int l = 0; l < d.levels; ++l) {
        std::int64_t w = std::max(1, d.width >> l), h = std::max(1, d.height >> l);
        std::int64_t z = d.target == GL_TEXTURE_3D ? std::max(1, d.depth >> l) : d.depth;
        bytes += w * h * z * bytesPerTexel(d.format);
    }
    return bytes;
}

bool poisonNewResources() {
    static const bool on = [] {
        const char* v = std::getenv("RTGI_POISON");
        return v && *v && std::string(v) != "0";
    }();
    return on;
}

namespace {
// GL reports a failed allocation only through glGetError (issue 16: a run
// under a memory cap died inside the driver later). Checked after every
// storage allocation; other pending errors are drained with it (KHR_debug,
// --debug, still reports them through its callback).
void checkAllocation(const std::string& what, std::int64_t bytes) {
    bool oom = false;
    for (GLenum e = glGetError(), n = 0; e != GL_NO_ERROR && n < 16; e = glGetError(), ++n)
        oom |= e == GL_OUT_OF_MEMORY;
    if (oom)
        throw OutOfMemory("the GPU ran out of memory allocating " + what + " (" + std::to_string(bytes >> 20) +
                          " MiB); lower the resolution or the setting that sizes it (see --max-memory)");
}
}  // namespace

Texture::Texture(MemoryLedger& ledger, std::string label, const TextureDesc& d) : desc_(d), label_(std::move(label)) {
    if (d.width < 1 || d.height < 1 || d.depth < 1 || d.levels < 1)
        throw std::runtime_error("texture '" + label_ + "' has an empty size");
    GLuint id = 0;
    glCreateTextures(d.target, 1, &id);
    handle_ = TextureHandle(id);
    if (d.target == GL_TEXTURE_3D || d.target == GL_TEXTURE_2D_ARRAY)
        glTextureStorage3D(id, d.levels, d.format, d.width, d.height, d.depth);
    else
        glTextureStorage2D(id, d.levels, d.format, d.width, d.height);
    const std::int64_t bytes = textureBytes(d);
    checkAllocation("texture '" + label_ + "'", bytes);
    handle_.label(label_);
    setSampling(d.levels > 1 ? GL_NEAREST_MIPMAP_NEAREST : GL_NEAREST, GL_NEAREST);
    // New storage is undefined in GL (NVIDIA hands out old memory, llvmpipe
    // zeros): start every texture at zero so that a pass reading history or an
    // accumulation before its first write sees 0, never garbage or NaN.
    zeroAllLevels();
    entry_ = LedgerEntry(&ledger, label_, bytes);
}

void Texture::zeroAllLevels() const {
    GLenum f = desc_.format;
    bool depth = f == GL_DEPTH_COMPONENT32F || f == GL_DEPTH_COMPONENT24 || f == GL_DEPTH_COMPONENT16;
    bool depthStencil = f == GL_DEPTH24_STENCIL8;
    bool integer = f == GL_R8UI || f == GL_R16UI || f == GL_R32UI || f == GL_R32I || f == GL_RG32UI ||
                   f == GL_RGBA8UI || f == GL_RGBA32UI;
    const std::uint32_t zeros[4] = {0, 0, 0, 0};
    for (int l = 0; l < desc_.levels; ++l) {
        if (depthStencil)
            glClearTexImage(id(), l, GL_DEPTH_STENCIL, GL_UNSIGNED_INT_24_8, zeros);
        else if (depth)
            glClearTexImage(id(), l, GL_DEPTH_COMPONENT, GL_FLOAT, zeros);
        else if (integer)
            glClearTexImage(id(), l, f == GL_R32I ? GL_RED_INTEGER : GL_RGBA_INTEGER,
                            f == GL_R32I ? GL_INT : GL_UNSIGNED_INT, zeros);
        else
            glClearTexImage(id(), l, GL_RGBA, GL_FLOAT, zeros);
    }
}

void Texture::setSampling(GLenum minFilter, GLenum magFilter, GLenum wrap) const {
    if (sampling_[0] == minFilter && sampling_[1] == magFilter && sampling_[2] == wrap) return;
    sampling_[0] = minFilter, sampling_[1] = magFilter, sampling_[2] = wrap;
    glTextureParameteri(id(), GL_TEXTURE_MIN_FILTER, GLint(minFilter));
    glTextureParameteri(id(), GL_TEXTURE_MAG_FILTER, GLint(magFilter));
    glTextureParameteri(id(), GL_TEXTURE_WRAP_S, GLint(wrap));
    glTextureParameteri(id(), GL_TEXTURE_WRAP_T, GLint(wrap));
    glTextureParameteri(id(), GL_TEXTURE_WRAP_R, GLint(wrap));
}

void Texture::clear(float r, float g, float b, float a) const {
    const float v[4] = {r, g, b, a};
    bool depth = desc_.format == GL_DEPTH_COMPONENT32F || desc_.format == GL_DEPTH_COMPONENT24 ||
                 desc_.format == GL_DEPTH_COMPONENT16;
    glClearTexImage(id(), 0, depth ? GL_DEPTH_COMPONENT : GL_RGBA, GL_FLOAT, v);
}

void Texture::clearInt(std::uint32_t v) const {
    const std::uint32_t c[4] = {v, v, v, v};
    glClearTexImage(id(), 0, GL_RGBA_INTEGER, GL_UNSIGNED_INT, c);
}

bool Texture::ensure(MemoryLedger& ledger, const std::string& label, const TextureDesc& desc) {
    // Identity is the object, not its label: a second name for the same
    // texture must never reallocate it (the label stays the first one).
    if (handle_ && desc == desc_) return false;
    reset();
    *this = Texture(ledger, label, desc);
    return true;
}

void Texture::reset() {
    handle_.reset();
    sampling_[0] = sampling_[1] = sampling_[2] = 0;
    entry_ = LedgerEntry();
    desc_ = {};
}

Buffer::Buffer(MemoryLedger& ledger, std::string label, std::int64_t bytes, const void* data, GLbitfield flags)
    : size_(bytes), label_(std::move(label)) {
    GLuint id = 0;
    glCreateBuffers(1, &id);
    handle_ = BufferHandle(id);
    glNamedBufferStorage(id, std::max<std::int64_t>(bytes, 4), data, flags);
    checkAllocation("buffer '" + label_ + "'", bytes);
    if (!data && poisonNewResources()) {
        // A driver hands out recycled memory (NVIDIA) where llvmpipe gives
        // zeros: with RTGI_POISON=1 every new buffer starts as 0xA5 bytes, so
        // a pass that reads before it writes fails on llvmpipe too.
        const std::uint32_t poison = 0xA5A5A5A5u;
        glClearNamedBufferData(id, GL_R32UI, GL_RED_INTEGER, GL_UNSIGNED_INT, &poison);
    }
    handle_.label(label_);
    entry_ = LedgerEntry(&ledger, label_, bytes);
}

void Buffer::upload(const void* data, std::int64_t bytes, std::int64_t offset) const {
    glNamedBufferSubData(id(), offset, bytes, data);
}
void Buffer::download(void* data, std::int64_t bytes, std::int64_t offset) const {
    // Shader writes reach glGetBufferSubData only after this barrier (GL 4.5
    // §7.12.2); without it NVIDIA returned stale bytes of a fresh buffer.
    glMemoryBarrier(GL_BUFFER_UPDATE_BARRIER_BIT);
    glGetNamedBufferSubData(id(), offset, bytes, data);
}
void Buffer::clearZero() const {
    const std::uint32_t z = 0;
    glClearNamedBufferData(id(), GL_R32UI, GL_RED_INTEGER, GL_UNSIGNED_INT, &z);
}
bool Buffer::ensure(MemoryLedger& ledger, const std::string& label, std::int64_t bytes) {
    if (handle_ && bytes == size_) return false;  // identity is the object, not its label
    reset();
    *this = Buffer(ledger, label, bytes);
    return true;
}
void Buffer::reset() {
    handle_.reset();
    entry_ = LedgerEntry();
    size_ = 0;
}

}  // namespace rtgi::gl
