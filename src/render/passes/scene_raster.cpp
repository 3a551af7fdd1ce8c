// rasterizeScene: the shared raster state of the G-buffer, shadow and RSM passes.
#include "gl/profiler.h"
#include "gl/program.h"
#include "render/gpu_scene.h"
#include "render/passes/core_passes.h"

namespace rtgi {

void rasterizeScene(FrameContext& ctx, const gl::Program& prog, GLuint fbo, glm::ivec2 size, int colorTargets,
                    bool depthBias) {
    glBindFramebuffer(GL_FRAMEBUFFER, fbo);
    glViewport(0, 0, size.x, size.y);
    glEnable(GL_DEPTH_TEST);
    glDepthFunc(GL_LESS);
    glDepthMask(GL_TRUE);
    glDisable(GL_CULL_FACE);
    glDisable(GL_BLEND);
    glColorMask(GL_TRUE, GL_TRUE, GL_TRUE, GL_TRUE);
    if (depthBias) {
        glEnable(GL_POLYGON_OFFSET_FILL);
        glPolygonOffset(1.5f, 2.0f);  // slope-scaled bias against shadow acne
    }
    const float zero[4] = {0, 0, 0, 0};
    for (int i = 0; i < colorTargets; ++i) glClearNamedFramebufferfv(fbo, GL_COLOR, i, zero);
    glClearNamedFramebufferfi(fbo, GL_DEPTH_STENCIL, 0, 1.0f, 0);
    glUseProgram(prog.id());
    ctx.gpuScene.bindTables();
    ctx.gpuScene.draw();
    gl::Profiler::noteDispatch();
    glDisable(GL_POLYGON_OFFSET_FILL);
    glBindFramebuffer(GL_FRAMEBUFFER, 0);
}

}  // namespace rtgi
