// Procedural plant textures of seed 000 §2.5-2.6.  Each takes the material's base colour (linear
// RGB) and returns the textured colour, writing a specular-map value in [0, 1] to `spec`.
// `scale` converts world units to noise units (the renderer sets it from the scene's size).

const float SYLVA_TAU = 6.28318530718;

// Bark: lengthwise cracks.  Stripes come from 3D Perlin noise whose y component (along the
// branch) is always 0, so they run straight along the branch; they then modulate 3D noise
// evaluated in global coordinates, which breaks them into cracks of finite length.
vec3 sylva_bark(vec3 base, vec2 uv, vec3 world, float scale, bool has_uv, out float spec) {
    vec3 ring;
    if (has_uv) {
        float a = SYLVA_TAU * uv.x;        // u runs around the branch
        ring = vec3(cos(a), 0.0, sin(a)) * 2.2;
    } else {
        ring = vec3(world.x * scale * 2.0, 0.0, world.z * scale * 2.0);  // global-Y fallback
    }
    float stripes = sylva_perlin(ring * 1.7 + vec3(0.0, 0.0, 0.0))
                  + 0.5 * sylva_perlin(ring * 3.9 + vec3(5.3, 0.0, 1.7));
    float global = sylva_fbm(world * scale * 0.7 + vec3(0.0, 0.5, 0.0), 3, 0.5);
    float crack = 1.0 - smoothstep(0.03, 0.17, abs(stripes));
    crack *= smoothstep(-0.35, 0.05, global);
    float tone = 0.78 + 0.5 * stripes * (0.6 + 0.4 * global);
    spec = 0.25 * (1.0 - crack);
    return base * tone * (1.0 - 0.75 * crack);
}

// Leaf: u runs across the blade (main vein at u = 0.5), v from base (0) to tip (1).  The main
// vein is brightest, side veins are a sine of the position, edges are slightly darker to suggest
// curvature.  No randomness.
vec3 sylva_leaf(vec3 base, vec2 uv, out float spec) {
    float ax = abs(uv.x - 0.5);
    float main_vein = 1.0 - smoothstep(0.012, 0.035, ax);
    float phase = uv.y * 7.0 - ax * 5.0;  // side veins sweep towards the tip
    float side = smoothstep(0.82, 0.98, sin(SYLVA_TAU * phase));
    side *= (1.0 - smoothstep(0.32, 0.48, ax)) * smoothstep(0.02, 0.06, ax);
    float edge = smoothstep(0.18, 0.5, ax);
    vec3 bright = min(base * 1.7 + vec3(0.06, 0.07, 0.03), vec3(1.0));
    vec3 c = base * (1.0 - 0.4 * edge);
    c = mix(c, bright, max(main_vein, 0.55 * side));
    spec = 0.6 * (1.0 - main_vein);
    return c;
}

// Grass: two 2D Perlin noises (3D noise on the plane z = 0.37, off the lattice), the second at
// a shifted position and another frequency.  The noise is signed, so no abs(position) is
// needed and there is no mirrored cross at the origin.
vec3 sylva_grass(vec3 base, vec3 world, float scale, out float spec) {
    vec2 p = world.xz * scale;
    float a = sylva_perlin(vec3(p * 1.3, 0.37));
    float b = sylva_perlin(vec3(p * 5.1 + vec2(17.31, 41.73), 0.37));
    float blades = sylva_perlin(vec3(p * vec2(40.0, 43.0) + vec2(3.1, 7.9), 0.61));
    float g = 0.78 + 0.3 * a + 0.18 * b + 0.1 * blades;
    vec3 c = base * g;
    c = mix(c, c * vec3(1.25, 1.1, 0.55), clamp(0.8 * a, 0.0, 1.0));  // dry patches
    spec = 0.05;
    return c;
}
