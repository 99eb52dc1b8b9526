// Procedural plant textures of seed 000 §2.5-2.6.  Each takes the material's base colour (linear
// RGB) and returns the textured colour, writing a specular-map value in [0, 1] to `spec`.
// `scale` converts world units to noise units (the renderer sets it from the scene's size).

const float SYLVA_TAU = 6.28318530718;

// Bark: lengthwise cracks, in the stem's own coordinates (seed 002's bark that follows the
// stem): u runs around the stem (period 1) and v along it, in circumferences of the stem's
// base radius (sylva's branch and tree meshers write both), so the grain scales with the
// radius: a trunk and a twig carry the same number of cracks around, at their own size.
// Stripes are Perlin noise stretched along v (12 cells around to every cell along), so they
// run along the stem; a rounder noise (8 around, 4 along per circumference) breaks them into
// cracks of finite length.  Both lattices repeat once per unit of u and v, so the pattern joins
// around the stem and a baked image of the unit square tiles along it.
const vec3 SYLVA_BARK_STRIPES = vec3(24.0, 2.0, 256.0);
const vec3 SYLVA_BARK_BREAKUP = vec3(8.0, 4.0, 256.0);

void sylva_bark_fields(vec2 uv, out float stripes, out float global) {
    vec3 p = vec3(uv, 0.37);
    stripes = sylva_perlin_tiled(p * vec3(SYLVA_BARK_STRIPES.xy, 1.0), SYLVA_BARK_STRIPES)
            + 0.5 * sylva_perlin_tiled(p * vec3(2.0 * SYLVA_BARK_STRIPES.xy, 1.0)
                                       + vec3(0.0, 0.0, 5.3), 2.0 * SYLVA_BARK_STRIPES);
    global = sylva_fbm_tiled(p * vec3(SYLVA_BARK_BREAKUP.xy, 1.0) + vec3(0.0, 0.0, 1.9),
                             SYLVA_BARK_BREAKUP, 3, 0.5);
}

// The crack mask (1 in a crack) of the fields.
float sylva_bark_crack(float stripes, float global) {
    float crack = 1.0 - smoothstep(0.03, 0.17, abs(stripes));
    return crack * smoothstep(-0.35, 0.05, global);
}

// Relief for normal maps: cracks are grooves, stripes ridges.
float sylva_bark_height(vec2 uv) {
    float stripes, global;
    sylva_bark_fields(uv, stripes, global);
    return 0.35 * stripes - sylva_bark_crack(stripes, global);
}

vec3 sylva_bark(vec3 base, vec2 uv, vec3 world, float scale, bool has_uv, out float spec) {
    float stripes, global;
    if (has_uv) {
        sylva_bark_fields(uv, stripes, global);
    } else {  // no stem coordinates: stripes along global Y, broken in world space
        vec3 ring = vec3(world.x * scale * 2.0, 0.0, world.z * scale * 2.0);
        stripes = sylva_perlin(ring * 1.7) + 0.5 * sylva_perlin(ring * 3.9 + vec3(5.3, 0.0, 1.7));
        global = sylva_fbm(world * scale * 0.7 + vec3(0.0, 0.5, 0.0), 3, 0.5);
    }
    float crack = sylva_bark_crack(stripes, global);
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

// Leaf relief for normal maps: the veins stand out of the blade.
float sylva_leaf_height(vec2 uv) {
    float ax = abs(uv.x - 0.5);
    float main_vein = 1.0 - smoothstep(0.012, 0.035, ax);
    float side = smoothstep(0.82, 0.98, sin(SYLVA_TAU * (uv.y * 7.0 - ax * 5.0)));
    side *= (1.0 - smoothstep(0.32, 0.48, ax)) * smoothstep(0.02, 0.06, ax);
    return max(main_vein, 0.55 * side) - 0.3 * smoothstep(0.18, 0.5, ax);
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

// Grass over a tile of uv (the baked ground image): the same noises as sylva_grass, on lattices
// that repeat once per unit of uv (4, 16 and 128 cells across), so the image tiles.
vec3 sylva_grass_tiled(vec3 base, vec2 uv, out float spec) {
    float a = sylva_perlin_tiled(vec3(uv * 4.0, 0.37), vec3(4.0, 4.0, 256.0));
    float b = sylva_perlin_tiled(vec3(uv * 16.0, 5.37), vec3(16.0, 16.0, 256.0));
    float blades = sylva_perlin_tiled(vec3(uv * 128.0, 0.61), vec3(128.0, 128.0, 256.0));
    float g = 0.78 + 0.3 * a + 0.18 * b + 0.1 * blades;
    vec3 c = base * g;
    c = mix(c, c * vec3(1.25, 1.1, 0.55), clamp(0.8 * a, 0.0, 1.0));
    spec = 0.05;
    return c;
}
