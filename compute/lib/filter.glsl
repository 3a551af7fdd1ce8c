// Shared screen-space filter math (AO and SSR): edge-preserving weights,
// the temporal blend of seed 000 listing 11, depth-aware upsampling.
#pragma once

// Whether a neighbour's surface (linear depth depthS, normal nS) continues
// the centre's: not sky, relative depth difference at most depthThreshold,
// normal cosine not below normalThreshold. The blur's edge stop and the
// sparse ray-traced AO's fill (ao/rtao.comp) decide with it.
bool surfaceCompatible(float depthC, float depthS, vec3 nC, vec3 nS, float depthThreshold, float normalThreshold) {
    if (!(depthS > 0.0)) return false;  // sky
    if (abs(depthS - depthC) > depthThreshold * depthC) return false;
    return !(dot(nC, nS) < normalThreshold);  // a NaN normal does not stop (as the blur always did)
}

// Edge-preserving Gaussian tap weight ([FM08], seed 000 4.5): zero when the
// tap's surface is not compatible with the centre's; the caller renormalizes.
float bilateralWeight(float gaussian, float depthC, float depthS, vec3 nC, vec3 nS, float depthThreshold,
                      float normalThreshold) {
    return surfaceCompatible(depthC, depthS, nC, nS, depthThreshold, normalThreshold) ? gaussian : 0.0;
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

// Normal similarity of a low-resolution tap (lpv.apply_resolution=half): max(0, n.n')^8, so
// taps of a surface turned by 30 degrees keep 0.32, by 60 degrees 0.004. Zero normals
// (unknown) give 1: depth alone decides.
float upsampleNormalWeight(vec3 nFull, vec3 nLow) {
    if (!(dot(nFull, nFull) > 0.0) || !(dot(nLow, nLow) > 0.0)) return 1.0;
    float c = max(dot(normalize(nFull), normalize(nLow)), 0.0);
    float c2 = c * c, c4 = c2 * c2;
    return c4 * c4;
}

// Joint bilateral upsampling (SPEC 6.4) at the full-resolution texel centre uv whose linear depth
// is dFull: the 2x2 low taps around uv, bilinear weights times upsampleWeight; with useNormals,
// also times upsampleNormalWeight(nFull, lowGeometry.gba) (lowGeometry: depth in .r, view normal
// in .gba). A sky pixel takes only sky taps. When every weight vanishes, the tap nearest in depth.
// upsampleTaps computes the taps and weights once; upsampleApply applies them to any texture of
// the low resolution (lpv/upsample.comp upsamples two with one set).
struct UpsampleTaps {
    ivec2 q[4];
    float w[4];
    float wSum;
    int nearest, heaviest;
    float match;  // with useNormals: the best tap's upsampleSimilarity to the full-resolution pixel
    ivec2 wide;   // upsampleWiden: a texel of the 4x4 around, mixed in with weight wideK (0: none)
    float wideK;
};

// How well a low-resolution texel represents a full-resolution pixel, in (0, 1]: the depth weight
// scaled to 1 at equal depth (times the normal weight in upsampleSimilarity; 0 for sky).
float upsampleDepthSimilarity(float dFull, float dLow) { return 1e-3 / (1e-3 + abs(dLow - dFull) / dFull); }
float upsampleSimilarity(float dFull, vec3 nFull, vec4 g) {
    return g.r > 0.0 ? upsampleDepthSimilarity(dFull, g.r) * upsampleNormalWeight(nFull, g.gba) : 0.0;
}

UpsampleTaps upsampleTaps(sampler2D lowGeometry, vec2 uv, float dFull, bool useNormals, vec3 nFull) {
    ivec2 lowSize = textureSize(lowGeometry, 0);
    vec2 t = uv * vec2(lowSize) - 0.5;
    ivec2 base = ivec2(floor(t));
    vec2 f = t - vec2(base);
    UpsampleTaps u;
    u.wSum = 0.0;
    u.nearest = u.heaviest = 0;
    u.match = 0.0;
    u.wide = ivec2(0);
    u.wideK = 0.0;
    float bestDiff = 1e30, wMax = -1.0;
    bool skyFull = !(dFull > 0.0);
    for (int i = 0; i < 4; ++i) {
        ivec2 o = ivec2(i & 1, i >> 1);
        u.q[i] = clamp(base + o, ivec2(0), lowSize - 1);
        float bilinear = (o.x == 1 ? f.x : 1.0 - f.x) * (o.y == 1 ? f.y : 1.0 - f.y);
        vec4 g = texelFetch(lowGeometry, u.q[i], 0);
        float dLow = g.r;
        float diff = abs(dLow - dFull);
        if (diff < bestDiff) bestDiff = diff, u.nearest = i;
        float w = skyFull ? (!(dLow > 0.0) ? bilinear : 0.0) : upsampleWeight(bilinear, dFull, dLow);
        if (useNormals && !skyFull && dLow > 0.0) {
            float nw = upsampleNormalWeight(nFull, g.gba);
            w *= nw;
            u.match = max(u.match, upsampleDepthSimilarity(dFull, dLow) * nw);
        }
        u.w[i] = w;
        u.wSum += w;
        if (w > wMax) wMax = w, u.heaviest = i;
    }
    return u;
}

// A pixel none of whose four taps is its surface (u.match < minMatch: more than 10 % apart in depth
// or turned by more than ~56 degrees at minMatch 0.01) — the background next to a thin column
// whose half texels all chose the column — mixes in the best-matching texel of the 4x4 around it
// (lpv/upsample.comp; docs/lpv.md "Half-resolution apply"), with the weight
// clamp((10 minMatch - match) / (9 minMatch), 0, 1) (1 - match / its match): 1 for a pixel no tap matches
// (match <= minMatch) and a texel that does, falling to 0 as the taps' match reaches 10 minMatch or the
// texel's, so that the result is continuous in the depths (rounding moves it by little).
void upsampleWiden(inout UpsampleTaps u, sampler2D lowGeometry, vec2 uv, float dFull, vec3 nFull, float minMatch) {
    if (!(dFull > 0.0) || u.match >= 10.0 * minMatch) return;
    ivec2 lowSize = textureSize(lowGeometry, 0);
    ivec2 base = ivec2(floor(uv * vec2(lowSize) - 0.5)) - 1;
    float best = 0.0;
    for (int j = 0; j < 4; ++j)
        for (int i = 0; i < 4; ++i) {
            if ((i == 1 || i == 2) && (j == 1 || j == 2)) continue;  // the four taps
            ivec2 q = clamp(base + ivec2(i, j), ivec2(0), lowSize - 1);
            float m = upsampleSimilarity(dFull, nFull, texelFetch(lowGeometry, q, 0));
            if (m > best) best = m, u.wide = q;
        }
    if (best > u.match) u.wideK = clamp((10.0 * minMatch - u.match) / (9.0 * minMatch), 0.0, 1.0) * (1.0 - u.match / best);
}

vec4 upsampleApply(sampler2D low, UpsampleTaps u) {
    vec4 v[4];
    for (int i = 0; i < 4; ++i) v[i] = texelFetch(low, u.q[i], 0);
    if (!(u.wSum > 1e-6)) return u.wideK > 0.0 ? mix(v[u.nearest], texelFetch(low, u.wide, 0), u.wideK) : v[u.nearest];
    // The weighted mean as the heaviest tap plus the weighted mean of the differences to it: a
    // constant field comes back bit-exact whatever the divide's rounding (an AO of 1, a sky alpha
    // of 1; a reciprocal-multiply divide of sum by wSum can give 1 - 2^-24, which a 16-bit store
    // that truncates keeps as 1 - 2^-11).
    vec4 ref = v[u.heaviest], sum = vec4(0.0);
    for (int i = 0; i < 4; ++i) sum += u.w[i] * (v[i] - ref);
    vec4 r = ref + sum / u.wSum;
    return u.wideK > 0.0 ? mix(r, texelFetch(low, u.wide, 0), u.wideK) : r;
}

vec4 upsampleJoint(sampler2D low, sampler2D lowGeometry, vec2 uv, float dFull, bool useNormals, vec3 nFull) {
    return upsampleApply(low, upsampleTaps(lowGeometry, uv, dFull, useNormals, nFull));
}
