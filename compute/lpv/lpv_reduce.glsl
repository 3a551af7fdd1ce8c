// Workgroup pre-reduction of fp32 image atomics (lpv.inject, lpv.inject_geometry).
// A tile of RSM or G-buffer texels falls into a handful of cells: every
// invocation adds its LPV_REDUCE_CHANNELS values into a shared-memory slot of
// its cell (open addressing on the cell key), and after a barrier one
// invocation per (slot, channel) issues the single global atomic of the
// workgroup. Invocations whose key finds no slot within LPV_REDUCE_PROBES
// probes (more distinct cells than slots) add globally themselves, so the
// result is the same sum in another order (docs/lpv.md, "Costs").
// The includer defines LPV_REDUCE_CHANNELS and, before including,
//   void lpvGlobalAdd(uint key, int channel, float value);
// Every invocation of the workgroup must call lpvReduceBegin() and
// lpvReduceEnd() (barriers); lpvReduceAdd() only where it has a contribution.
// The includer enables GL_NV_shader_atomic_float first (float atomicAdd on shared memory).

const uint LPV_REDUCE_SLOTS = 32u;  // power of two
const uint LPV_REDUCE_PROBES = 8u;
const uint LPV_NO_KEY = 0xffffffffu;

shared uint sLpvKeys[LPV_REDUCE_SLOTS];
shared float sLpvSums[LPV_REDUCE_SLOTS * LPV_REDUCE_CHANNELS];

uint lpvGroupSize() { return gl_WorkGroupSize.x * gl_WorkGroupSize.y * gl_WorkGroupSize.z; }

void lpvReduceBegin() {
    for (uint i = gl_LocalInvocationIndex; i < LPV_REDUCE_SLOTS; i += lpvGroupSize()) sLpvKeys[i] = LPV_NO_KEY;
    for (uint i = gl_LocalInvocationIndex; i < LPV_REDUCE_SLOTS * LPV_REDUCE_CHANNELS; i += lpvGroupSize())
        sLpvSums[i] = 0.0;
    barrier();
}

void lpvReduceAdd(uint key, float v[LPV_REDUCE_CHANNELS]) {
    uint h = (key * 2654435761u) >> 27u;  // Fibonacci hash, top 5 bits: 0..31
    for (uint p = 0u; p < LPV_REDUCE_PROBES; ++p) {
        uint s = (h + p) & (LPV_REDUCE_SLOTS - 1u);
        uint prev = atomicCompSwap(sLpvKeys[s], LPV_NO_KEY, key);
        if (prev == LPV_NO_KEY || prev == key) {
            for (int k = 0; k < LPV_REDUCE_CHANNELS; ++k)
                if (v[k] != 0.0) atomicAdd(sLpvSums[s * uint(LPV_REDUCE_CHANNELS) + uint(k)], v[k]);
            return;
        }
    }
    for (int k = 0; k < LPV_REDUCE_CHANNELS; ++k)
        if (v[k] != 0.0) lpvGlobalAdd(key, k, v[k]);
}

void lpvReduceEnd() {
    memoryBarrierShared();
    barrier();
    for (uint i = gl_LocalInvocationIndex; i < LPV_REDUCE_SLOTS * LPV_REDUCE_CHANNELS; i += lpvGroupSize()) {
        uint key = sLpvKeys[i / uint(LPV_REDUCE_CHANNELS)];
        float v = sLpvSums[i];
        if (key != LPV_NO_KEY && v != 0.0) lpvGlobalAdd(key, int(i % uint(LPV_REDUCE_CHANNELS)), v);
    }
}
