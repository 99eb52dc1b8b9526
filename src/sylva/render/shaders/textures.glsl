// Procedural plant textures of seed 000 §2.5-2.6.  Each takes the material's base colour (linear
// RGB) and returns the textured colour, writing a specular-map value in [0, 1] to `spec`.
// `scale` converts world units to noise units (the renderer sets it from the scene's size).

#if defined(TEXTURE_KIND) && (TEXTURE_KIND == 2 || TEXTURE_KIND == 3)
#include "surfaces.glsl"

// Bark and leaf are texture graphs (sylva.texture.graph.surface): surfaces.glsl is their GLSL,
// generated from the same graphs the exports bake on the CPU, so a view and an exported image
// show one function.  Each returns a vec4 of the surface's (u, v).

// Bark, in the stem's own coordinates: u around the stem (period 1), v along it in
// circumferences of the stem's base radius (sylva's branch and tree meshers write both), so
// the grain follows the radius.  The graph's channels: r tone, g specular map, b relief.
vec4 sylva_bark_at(vec2 uv, vec3 world, float scale, bool has_uv) {
    if (has_uv) return sylva_bark_graph(vec3(uv, 0.0));
    // no stem coordinates: the graph laid on world space, stripes along global Y
    return sylva_bark_graph(vec3((world.x + world.z) * scale * 0.15, world.y * scale * 0.15,
                                 0.0));
}

// Relief for normal maps: cracks are grooves, stripes ridges.
float sylva_bark_height(vec2 uv) {
    return sylva_bark_graph(vec3(uv, 0.0)).b;
}

vec3 sylva_bark(vec3 base, vec2 uv, vec3 world, float scale, bool has_uv, out float spec) {
    vec4 t = sylva_bark_at(uv, world, scale, has_uv);
    spec = t.g;
    return base * t.r;
}

// Leaf: u runs across the blade (main vein at u = 0.5), v from base (0) to tip (1).  The
// graph's channels: r darkening towards the edges, g vein mask, b specular map, a relief.
vec3 sylva_leaf(vec3 base, vec2 uv, out float spec) {
    vec4 t = sylva_leaf_graph(vec3(uv, 0.0));
    vec3 bright = min(base * 1.7 + vec3(0.06, 0.07, 0.03), vec3(1.0));
    spec = t.b;
    return mix(base * t.r, bright, t.g);
}

// Leaf relief for normal maps: the veins stand out of the blade.
float sylva_leaf_height(vec2 uv) {
    return sylva_leaf_graph(vec3(uv, 0.0)).a;
}

#endif

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
