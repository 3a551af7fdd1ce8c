#include "view/display.h"

#include "compute/lib/view_shared.h"


#include <algorithm>

namespace rtgi::view {

namespace {

bool displayable(const gl::Texture* t) {
    if (!t || !*t || t->desc().target != GL_TEXTURE_2D) return false;
    switch (t->format()) {
        case GL_R8: case GL_RG8: case GL_RGBA8: case GL_R16F: case GL_RG16F: case GL_RGBA16F: case GL_R32F:
        case GL_RG32F: case GL_RGBA32F: case GL_R11F_G11F_B10F: case GL_DEPTH_COMPONENT32F: case GL_DEPTH_COMPONENT24:
            return true;
        default: return false;  // integer formats need their own decoding
    }
}

// How a shared resource is made visible (by what it holds, not its format).
DisplayImage mapResource(const std::string& name, const gl::Texture* t, float exposure) {
    DisplayImage d{name, t, 3, 1.0f};
    bool single = t->format() == GL_R8 || t->format() == GL_R16F || t->format() == GL_R32F ||
                  t->format() == GL_DEPTH_COMPONENT32F || t->format() == GL_DEPTH_COMPONENT24;
    if (name == "ldr") d.mode = 0;
    else if (name == "gbuffer.linearDepth") d.mode = 4;
    else if (name == "gbuffer.normal" || name == "gbuffer.velocity" || name == "bentNormal" || name == "s3ho") d.mode = 2;
    else if (name == "gbuffer.albedo" || name == "gbuffer.material" || name == "ao" || name == "specularOcclusion" ||
             single) {
        d.mode = single ? 3 : 0;
    } else {
        d.mode = 1;  // radiance: direct, indirect, specular, hdr, emissive, histories
        d.scale = exposure;
    }
    return d;
}

}  // namespace

std::vector<DisplayImage> displayImages(Renderer& r) {
    std::vector<DisplayImage> out;
    FrameResources& res = r.resources();
    float exposure = r.settings().post.exposure;
    if (displayable(&res.ldr)) out.push_back({"final", &res.ldr, 0, 1.0f});
    for (auto& [name, tex] : namedResources(res))
        if (name != "ldr" && displayable(tex)) out.push_back(mapResource(name, tex, exposure));
    for (auto& p : r.passes())
        for (auto& d : r.debugImages(*p))
            if (displayable(d.tex)) {
                // Debug images are written to PNG as value x scale without sRGB (run.cpp): show them the same way.
                bool single = d.tex->format() == GL_R8 || d.tex->format() == GL_R16F || d.tex->format() == GL_R32F;
                out.push_back({d.name, d.tex, single ? 3 : 0, d.scale});
            }
    return out;
}

ScreenPainter::ScreenPainter() {
    // Core profile needs a bound VAO even when the vertex shaders pull their data.
    GLuint v = 0;
    glCreateVertexArrays(1, &v);
    vao_ = gl::VertexArrayHandle(v);
    vao_.label("view.vao");
}

void ScreenPainter::drawImage(gl::ProgramCache& programs, const DisplayImage& img, glm::ivec2 viewport, float farPlane,
                              const PresentOptions& opts) {
    const gl::Program& prog = programs.raster("view/fullscreen.vert", "view/present.frag");
    glBindFramebuffer(GL_FRAMEBUFFER, 0);
    glViewport(0, 0, viewport.x, viewport.y);
    glDisable(GL_DEPTH_TEST);
    glDisable(GL_BLEND);
    glDisable(GL_CULL_FACE);
    glDisable(GL_SCISSOR_TEST);
    glColorMask(GL_TRUE, GL_TRUE, GL_TRUE, GL_TRUE);
    glUseProgram(prog.id());
    const bool compare = opts.compare != RTGI_VIEW_COMPARE_OFF && opts.reference && *opts.reference;
    prog.set(RTGI_VIEW_LOC_MODE, img.mode);
    prog.set(RTGI_VIEW_LOC_SCALE, img.scale * opts.exposure);
    prog.set(RTGI_VIEW_LOC_FAR, farPlane);
    prog.set(RTGI_VIEW_LOC_CHANNEL, opts.channel);
    prog.set(RTGI_VIEW_LOC_COMPARE, compare ? opts.compare : RTGI_VIEW_COMPARE_OFF);
    prog.set(RTGI_VIEW_LOC_SPLIT, opts.split);
    prog.set(RTGI_VIEW_LOC_REF_MODE, opts.referenceMode);
    prog.set(RTGI_VIEW_LOC_HEAT_MAX, opts.heatMax);
    // Producer: the renderer's passes wrote these textures with imageStore or as render targets.
    glMemoryBarrier(GL_TEXTURE_FETCH_BARRIER_BIT);
    img.tex->setSampling(GL_LINEAR, GL_LINEAR);
    glBindTextureUnit(RTGI_VIEW_TEX_IMAGE, img.tex->id());
    // The reference unit always holds a texture (the image itself when there is none).
    const gl::Texture& ref = compare ? *opts.reference : *img.tex;
    ref.setSampling(GL_LINEAR, GL_LINEAR);
    glBindTextureUnit(RTGI_VIEW_TEX_REFERENCE, ref.id());
    glBindVertexArray(vao_.id());
    glDrawArrays(GL_TRIANGLES, 0, 3);
}

void writeScreenshot(const std::string& path, const DisplayImage& img, float farPlane) {
    FloatImage im = readTexture(*img.tex);
    int ch = im.channels;
    for (std::size_t i = 0; i < im.data.size(); i += std::size_t(ch)) {
        float* p = &im.data[i];
        for (int c = 0; c < std::min(ch, 3); ++c) {
            float v = p[c];
            if (img.mode == 2) v = v * 0.5f + 0.5f;
            else if (img.mode == 4) v = farPlane > 0 ? p[0] / farPlane : 0.0f;
            else if (img.mode == 3) v = p[0];
            p[c] = v;
        }
    }
    // Modes 1 and 3 are scaled (1 also sRGB-encoded) by writePng, as run.cpp writes them.
    float scale = img.mode == 1 || img.mode == 3 ? img.scale : 1.0f;
    writePng(path, im, scale, img.mode == 1);
}

void writeWindowScreenshot(const std::string& path, glm::ivec2 size) {
    std::vector<std::uint8_t> px(std::size_t(size.x) * std::size_t(size.y) * 4);
    glBindFramebuffer(GL_READ_FRAMEBUFFER, 0);
    glReadBuffer(GL_BACK);
    glPixelStorei(GL_PACK_ALIGNMENT, 1);
    glReadPixels(0, 0, size.x, size.y, GL_RGBA, GL_UNSIGNED_BYTE, px.data());
    FloatImage im;
    im.width = size.x;
    im.height = size.y;
    im.data.resize(px.size());
    for (std::size_t i = 0; i < px.size(); ++i) im.data[i] = float(px[i]) / 255.0f;
    writePng(path, im);
}

}  // namespace rtgi::view
