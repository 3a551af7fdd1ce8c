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

// Joint bilateral upsampling weight of one low-resolution tap: bilinear
// weight times a depth similarity 1 / (eps + |dz|/z).
float upsampleWeight(float bilinear, float depthFull, float depthLow) {
    if (!(depthLow > 0.0)) return 0.0;
    return bilinear / (1e-3 + abs(depthLow - depthFull) / depthFull);
}
