// VIEW family: texture units, uniform locations and modes of rtgi-view's
// presentation shader (compute/view/present.frag) and its C++ side
// (src/view/display.cpp), so neither side holds a literal
// (docs/architecture.md, "Binding slots").
#ifndef RTGI_VIEW_SHARED_H
#define RTGI_VIEW_SHARED_H

// Texture units.
#define RTGI_VIEW_TEX_IMAGE 0      // the displayed image (or the technique's output in a comparison)
#define RTGI_VIEW_TEX_REFERENCE 1  // the live reference's mean

// Uniform locations.
#define RTGI_VIEW_LOC_MODE 0        // int: RTGI_VIEW_MODE_* of the image
#define RTGI_VIEW_LOC_SCALE 1       // float: exposure x the image's scale
#define RTGI_VIEW_LOC_FAR 2         // float: far plane (depth mode)
#define RTGI_VIEW_LOC_CHANNEL 3     // int: 0 rgb, 1 r, 2 g, 3 b, 4 a (shown as grey)
#define RTGI_VIEW_LOC_COMPARE 4     // int: RTGI_VIEW_COMPARE_*
#define RTGI_VIEW_LOC_SPLIT 5       // float: split position in [0,1] of the window width
#define RTGI_VIEW_LOC_REF_MODE 6    // int: mode of the reference texture
#define RTGI_VIEW_LOC_HEAT_MAX 7    // float: |Δ luminance| shown as the brightest heat-map colour

// Modes: how a texture's values become display values.
#define RTGI_VIEW_MODE_READY 0     // display-ready (LDR)
#define RTGI_VIEW_MODE_RADIANCE 1  // linear radiance x scale -> sRGB
#define RTGI_VIEW_MODE_SIGNED 2    // signed vector x 0.5 + 0.5
#define RTGI_VIEW_MODE_GREY 3      // channel 0 x scale, grey
#define RTGI_VIEW_MODE_DEPTH 4     // linear depth / far

// Comparison layouts.
#define RTGI_VIEW_COMPARE_OFF 0        // the image alone
#define RTGI_VIEW_COMPARE_SPLIT 1      // technique left of the split, reference right
#define RTGI_VIEW_COMPARE_REFERENCE 2  // the reference alone (the toggle)
#define RTGI_VIEW_COMPARE_HEATMAP 3    // |Δ luminance| heat map
#define RTGI_VIEW_COMPARE_SIDE 4       // side by side, each at half size

// stage interface of the presentation shaders
#define RTGI_VIEW_VARY_UV 0
#define RTGI_VIEW_OUT_COLOR 0

#endif
