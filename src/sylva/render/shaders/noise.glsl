// Improved Perlin noise (Perlin 2002) in 3D, hashed instead of a permutation table so that it
// needs no texture.  Output lies in about [-1, 1]; the value is 0 on integer lattice points.
// Octave sums follow seed 000 §4.6: sum_i a p^i noise(f 2^i x).

uint sylva_hash(uvec3 p) {
    uint h = (p.x * 0x8da6b343u) ^ (p.y * 0xd8163841u) ^ (p.z * 0xcb1ab31fu);
    h ^= h >> 16u;
    h *= 0x7feb352du;
    h ^= h >> 15u;
    h *= 0x846ca68bu;
    h ^= h >> 16u;
    return h;
}

float sylva_grad(uint hash, vec3 p) {
    uint h = hash & 15u;
    float u = h < 8u ? p.x : p.y;
    float v = h < 4u ? p.y : ((h == 12u || h == 14u) ? p.x : p.z);
    return ((h & 1u) == 0u ? u : -u) + ((h & 2u) == 0u ? v : -v);
}

float sylva_perlin(vec3 p) {
    vec3 i = floor(p);
    vec3 f = p - i;
    uvec3 c = uvec3(ivec3(i));
    vec3 w = f * f * f * (f * (f * 6.0 - 15.0) + 10.0);
    float n000 = sylva_grad(sylva_hash(c), f);
    float n100 = sylva_grad(sylva_hash(c + uvec3(1u, 0u, 0u)), f - vec3(1.0, 0.0, 0.0));
    float n010 = sylva_grad(sylva_hash(c + uvec3(0u, 1u, 0u)), f - vec3(0.0, 1.0, 0.0));
    float n110 = sylva_grad(sylva_hash(c + uvec3(1u, 1u, 0u)), f - vec3(1.0, 1.0, 0.0));
    float n001 = sylva_grad(sylva_hash(c + uvec3(0u, 0u, 1u)), f - vec3(0.0, 0.0, 1.0));
    float n101 = sylva_grad(sylva_hash(c + uvec3(1u, 0u, 1u)), f - vec3(1.0, 0.0, 1.0));
    float n011 = sylva_grad(sylva_hash(c + uvec3(0u, 1u, 1u)), f - vec3(0.0, 1.0, 1.0));
    float n111 = sylva_grad(sylva_hash(c + uvec3(1u, 1u, 1u)), f - vec3(1.0, 1.0, 1.0));
    float x00 = mix(n000, n100, w.x);
    float x10 = mix(n010, n110, w.x);
    float x01 = mix(n001, n101, w.x);
    float x11 = mix(n011, n111, w.x);
    return mix(mix(x00, x10, w.y), mix(x01, x11, w.y), w.z);
}

// Octave sum normalised by the sum of amplitudes (so it stays in about [-1, 1]).
float sylva_fbm(vec3 p, int octaves, float persistence) {
    float sum = 0.0;
    float amp = 1.0;
    float norm = 0.0;
    for (int i = 0; i < octaves; ++i) {
        sum += amp * sylva_perlin(p);
        norm += amp;
        amp *= persistence;
        p *= 2.0;
    }
    return sum / norm;
}

// Perlin noise whose lattice repeats every `period` cells along each axis (whole numbers), so
// that a pattern made of it tiles: sylva_perlin_tiled(p + period, period) == sylva_perlin_tiled(p,
// period).  Used in stem coordinates (u around, v along), where bark must join around the stem
// and baked images must tile.
float sylva_perlin_tiled(vec3 p, vec3 period) {
    vec3 i = floor(p);
    vec3 f = p - i;
    ivec3 a = ivec3(mod(i, period));
    ivec3 b = ivec3(mod(i + 1.0, period));
    vec3 w = f * f * f * (f * (f * 6.0 - 15.0) + 10.0);
    float n000 = sylva_grad(sylva_hash(uvec3(a.x, a.y, a.z)), f);
    float n100 = sylva_grad(sylva_hash(uvec3(b.x, a.y, a.z)), f - vec3(1.0, 0.0, 0.0));
    float n010 = sylva_grad(sylva_hash(uvec3(a.x, b.y, a.z)), f - vec3(0.0, 1.0, 0.0));
    float n110 = sylva_grad(sylva_hash(uvec3(b.x, b.y, a.z)), f - vec3(1.0, 1.0, 0.0));
    float n001 = sylva_grad(sylva_hash(uvec3(a.x, a.y, b.z)), f - vec3(0.0, 0.0, 1.0));
    float n101 = sylva_grad(sylva_hash(uvec3(b.x, a.y, b.z)), f - vec3(1.0, 0.0, 1.0));
    float n011 = sylva_grad(sylva_hash(uvec3(a.x, b.y, b.z)), f - vec3(0.0, 1.0, 1.0));
    float n111 = sylva_grad(sylva_hash(uvec3(b.x, b.y, b.z)), f - vec3(1.0, 1.0, 1.0));
    float x00 = mix(n000, n100, w.x);
    float x10 = mix(n010, n110, w.x);
    float x01 = mix(n001, n101, w.x);
    float x11 = mix(n011, n111, w.x);
    return mix(mix(x00, x10, w.y), mix(x01, x11, w.y), w.z);
}

// Octave sum of sylva_perlin_tiled (each octave doubles the frequency and the period).
float sylva_fbm_tiled(vec3 p, vec3 period, int octaves, float persistence) {
    float sum = 0.0;
    float amp = 1.0;
    float norm = 0.0;
    for (int i = 0; i < octaves; ++i) {
        sum += amp * sylva_perlin_tiled(p, period);
        norm += amp;
        amp *= persistence;
        p *= 2.0;
        period *= 2.0;
    }
    return sum / norm;
}
