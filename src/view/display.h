#pragma once
// What rtgi-view can show: the final image, every 2D texture of
// FrameResources and every debug image the passes declare, each with the mapping that
// makes it visible (present.frag modes, compute/lib/view_shared.h).
#include "gl/handles.h"
#include "gl/image_io.h"
#include "gl/program.h"
#include "gl/resources.h"
#include "render/renderer.h"

#include <string>
#include <vector>

namespace rtgi::view {

struct DisplayImage {
    std::string name;
    const gl::Texture* tex = nullptr;
    int mode = 0;       // RTGI_VIEW_MODE_*: 0 ready, 1 radiance, 2 signed, 3 grey, 4 depth
    float scale = 1.0f;
};

// The images of the current frame, "final" first; only 2D float/unorm textures.
std::vector<DisplayImage> displayImages(Renderer& renderer);

// The image as it is displayed, for screenshots (the final image is written
// exactly as rtgi-bench writes final.png).
void writeScreenshot(const std::string& path, const DisplayImage& img, float farPlane);
// The window's back buffer (image + overlay) as drawn this frame.
void writeWindowScreenshot(const std::string& path, glm::ivec2 size);

// How present.frag shows the image (compute/lib/view_shared.h).
struct PresentOptions {
    float exposure = 1.0f;   // multiplies the image's scale (radiance and grey modes)
    int channel = 0;         // 0 rgb, 1 r, 2 g, 3 b, 4 a
    int compare = 0;         // RTGI_VIEW_COMPARE_*: with `reference`
    float split = 0.5f;      // split position (fraction of the width)
    const gl::Texture* reference = nullptr;
    int referenceMode = 3;   // RTGI_VIEW_MODE_* of the reference
    float heatMax = 0.1f;
};

// Draws into the window's default framebuffer.
class ScreenPainter {
public:
    ScreenPainter();
    // `img` over the whole viewport.
    void drawImage(gl::ProgramCache& programs, const DisplayImage& img, glm::ivec2 viewport, float farPlane,
                   const PresentOptions& opts = {});

private:
    gl::VertexArrayHandle vao_;
};

}  // namespace rtgi::view
