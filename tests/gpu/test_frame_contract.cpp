// The declared frame contract on a GL context: shared textures are allocated
// once by the renderer, by handle (never by label), and stay the same object
// from frame to frame; a texture's label never causes a reallocation.
#include "gpu_fixture.h"
#include "scene/builtin.h"

using namespace rtgi;
using namespace rtgi::test;

TEST_CASE("Texture::ensure: the description decides, not the label") {
    GpuFixture gpu;
    gl::MemoryLedger ledger;
    gl::Texture t;
    CHECK(t.ensure(ledger, "indirectDiffuse", {GL_TEXTURE_2D, GL_RGBA16F, 8, 8}));
    GLuint id = t.id();
    CHECK_FALSE(t.ensure(ledger, "indirect_diffuse", {GL_TEXTURE_2D, GL_RGBA16F, 8, 8}));
    CHECK(t.id() == id);
    CHECK(t.label() == "indirectDiffuse");
    CHECK(t.ensure(ledger, "indirectDiffuse", {GL_TEXTURE_2D, GL_RGBA16F, 9, 8}));  // a new size is a new texture
}

TEST_CASE("shared resources: allocated by the renderer once, the same objects every frame, only what is written") {
    GpuFixture gpu;
    gl::Profiler prof(false);
    Scene s = loadBuiltin("cornell");
    Settings st = smallLpvSettings();
    st.lpv.mode = Toggle::On;
    st.ao.variant = AoSettings::Variant::Gtao;
    st.ao.nearfield = 1.0f;
    st.ssr.tracer = SsrSettings::Tracer::Off;
    Renderer r(s, st, prof);
    Camera cam = resolveCamera(s, st);
    std::vector<GLuint> ids;
    View prev;
    for (unsigned f = 0; f < 3; ++f) {
        View v = makeView(cam, {24, 18}, f == 0 ? nullptr : &prev, f);
        r.render(v);
        prev = v;
        std::vector<GLuint> now;
        for (int i = 0; i < R::count; ++i) now.push_back(r.resources()[Resource{i}].id());
        if (f > 0) CHECK(now == ids);  // nothing reallocated after the first frame
        ids = now;
    }
    for (int i = 0; i < R::count; ++i) {
        const Resource res{i};
        INFO(resourceDesc(res).name);
        // Allocated exactly when a pass of the frame writes it, under its own name.
        CHECK(bool(r.resources()[res]) == r.plan().written(res));
        if (r.plan().written(res)) CHECK(r.ledger().entries().count(resourceDesc(res).name) == 1);
    }
    CHECK_FALSE(r.plan().written(R::specularOcclusion));  // ssr=off
    // The frame decides that ao.nearfield adds to lpv.apply's indirect light.
    CHECK(r.plan().table().find("+=indirectDiffuse") != std::string::npos);
}

// post.history's image is written by post.compose (one dispatch fewer than a copy): after a frame whose
// near-field light reads the previous frame's radiance, it holds this frame's hdr in half precision and
// the linear depth in alpha (the readers' disocclusion test); without a reader the plan drops it.
TEST_CASE("post.history holds the frame's hdr radiance (RGBA16F) and its linear depth, written by post.compose") {
    GpuFixture gpu;
    gl::Profiler prof(false);
    Scene s = loadBuiltin("cornell");
    Settings st = smallLpvSettings();
    st.ao.variant = AoSettings::Variant::Gtao;
    st.ao.nearfield = 1.0f;  // ao.nearfield reads the previous frame's history
    auto r = renderFrames(s, st, {24, 18}, prof, 2);
    REQUIRE(r->plan().written(R::history));
    FloatImage hist = readTexture(r->resources().history), hdr = readTexture(r->resources().hdr),
               depth = readTexture(r->resources().gbuffer.linearDepth);
    REQUIRE(hist.data.size() == hdr.data.size());
    std::size_t bad = 0, lit = 0;
    for (std::size_t i = 0; i < hdr.data.size(); i += 4) {
        for (std::size_t c = 0; c < 3; ++c) {
            // One half-precision rounding (2^-11 relative to nearest, 2^-10 truncated), plus the smallest normal half.
            if (std::abs(hist.data[i + c] - hdr.data[i + c]) > 1e-3f * std::abs(hdr.data[i + c]) + 6.2e-5f) ++bad;
            if (hdr.data[i + c] > 1e-3f) ++lit;
        }
        const float d = depth.data[i / 4 * std::size_t(depth.channels)];
        if (std::abs(hist.data[i + 3] - d) > 1e-3f * std::abs(d)) ++bad;
    }
    CHECK(bad == 0);
    CHECK(lit > hdr.data.size() / 8);  // a lit frame, not two empty images
    st.ao.nearfield = 0.0f;
    Renderer none(s, st, prof);
    CHECK_FALSE(none.plan().written(R::history));
}
