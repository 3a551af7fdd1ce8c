// Running per-pixel mean and M2 (sum of squared deviations from the mean)
// of a progressive estimate, in fp32 without cancellation: within a batch
// Welford's update (Welford 1962), across batches the pairwise merge of
// Chan, Golub & LeVeque 1979 (δ = mean_b − mean_a; mean = mean_a + δ·n_b/n;
// M2 = M2_a + M2_b + δ²·n_a·n_b/n). Summing x and x² in fp32, as before,
// loses the variance once Σx² is 2^24 times larger than it (a pixel of
// radiance 1000 with variance 0.1 after a few samples); these updates only
// ever add deviations. Variance = M2 / (n − 1).
#pragma once

struct Moments {
    vec3 mean;
    vec3 m2;
    float n;
};

Moments momentsEmpty() { return Moments(vec3(0.0), vec3(0.0), 0.0); }

void momentsAdd(inout Moments m, vec3 x) {
    m.n += 1.0;
    vec3 d = x - m.mean;
    m.mean += d / m.n;
    m.m2 += d * (x - m.mean);
}

Moments momentsMerge(Moments a, Moments b) {
    float n = a.n + b.n;
    if (!(n > 0.0)) return a;
    vec3 d = b.mean - a.mean;
    Moments r;
    r.n = n;
    r.mean = a.mean + d * (b.n / n);
    r.m2 = a.m2 + b.m2 + d * d * (a.n * b.n / n);
    return r;
}

// The accumulation images: rgb mean with n in alpha, and M2 in rgb.
Moments momentsLoad(vec4 meanN, vec4 m2) { return Moments(meanN.rgb, m2.rgb, meanN.a); }
