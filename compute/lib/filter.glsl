// Shared screen-space filter math (AO and SSR): edge-preserving weights,
// the temporal blend of seed 000 listing 11, depth-aware upsampling.
#pragma once

// Edge-preserving Gaussian tap weight ([FM08], seed 000 4.5): zero when the
// relative depth difference exceeds depthThreshold or the normals diverge
// below normalThreshold (cosine); the caller renormalizes.
float bilateralWeight(float gaussian, float depthC, float depthS, vec3 nC, vec3 nS, float depthThreshold,
                      float normalThreshold) {
    if (!(depthS > 0.0)) return 0.0;  // sky
    if (abs(depthS - depthC) > depthThreshold * depthC) return 0.0;
    if (dot(nC, nS) < normalThreshold) return 0.0;
    return gaussian;
}

// Seed 000 listing 11: history blend factor from the depth difference times
// the velocity's L1 length; 1 (take current) when the reprojected uv leaves
// [0.0001, 0.9999].
float temporalAlpha(float depthDifference, vec2 velocity, vec2 reprojectedUv) {
    const float alphaMin = 0.05, blendStrength = 100.0;
    float velocityFactor = dot(abs(velocity), vec2(1.0));
    float blendFactor = clamp(blendStrength * depthDifference * velocityFactor, 0.0, 1.0);
    float alpha = mix(alphaMin, 1.0, blendFactor);
    const float lowerBound = 0.0001, upperBound = 0.9999;
    if (reprojectedUv.x < lowerBound || reprojectedUv.y < lowerBound || reprojectedUv.x >= upperBound ||
        reprojectedUv.y >= upperBound)
        alpha = 1.0;
    return alpha;
}

// Disocclusion (docs/temporal.md, "Disocclusion"). Depth change per pixel of
// a linear-depth texture at p: per axis the smaller one-sided difference (a
// silhouette beside p does not widen its tolerance), sky neighbours ignored.
float depthSlopePerPixel(sampler2D depthTex, ivec2 p, ivec2 size, float depth) {
    float slope = 0.0;
    for (int axis = 0; axis < 2; ++axis) {
        float s = 1e30;
        for (int k = -1; k <= 1; k += 2) {
            ivec2 q = p;
            q[axis] += k;
            if (q[axis] < 0 || q[axis] >= size[axis]) continue;
            float dq = texelFetch(depthTex, q, 0).r;
            if (dq > 0.0) s = min(s, abs(dq - depth));
        }
        slope += s > 1e29 ? 0.0 : s;
    }
    return slope;
}

// How far a previous depth may lie from `expected`, the depth in the previous
// view of the point whose current depth is `depth`, and still be that surface:
// the depth slope over the reprojection's position error (1 pixel of bilinear
// footprint or tap offset and resolution change, plus the RG16F velocity's
// 2^-10 relative rounding), scaled to the previous depth, plus the stored
// depth's relative precision.
float disocclusionTolerance(float expected, float depth, float slopePerPixel, vec2 velocityPixels,
                            float relativePrecision) {
    float radius = 1.0 + exp2(-10.0) * length(velocityPixels);
    return radius * slopePerPixel * max(expected, 0.0) / depth + relativePrecision * abs(expected);
}

// True when the previous frame's depth sampled (bilinearly) at the
// reprojected position is another surface than that point.
bool historyDisoccluded(float historyDepth, float expected, float depth, float slopePerPixel,
                        vec2 velocityPixels, float relativePrecision) {
    if (!(historyDepth > 0.0)) return true;  // sky there in the previous frame
    return !(abs(historyDepth - expected) <=
             disocclusionTolerance(expected, depth, slopePerPixel, velocityPixels, relativePrecision));
}

// Joint bilateral upsampling weight of one low-resolution tap: bilinear
// weight times a depth similarity 1 / (eps + |dz|/z).
float upsampleWeight(float bilinear, float depthFull, float depthLow) {
    if (!(depthLow > 0.0)) return 0.0;
    return bilinear / (1e-3 + abs(depthLow - depthFull) / depthFull);
}
