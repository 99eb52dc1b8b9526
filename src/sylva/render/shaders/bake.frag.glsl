#version 330 core
// Bakes one procedural texture of textures.glsl over the unit square of uv (pixel centres),
// with the same functions the renderer draws with.  Outputs (float targets, linear):
//   0: albedo RGB, specular-map value;  1: relief height (for the normal map).
// TEXTURE_KIND: 2 bark, 3 leaf, 4 grass (as in phong.frag.glsl).

#include "noise.glsl"
#include "textures.glsl"

uniform vec3 u_color;   // linear base colour
uniform vec2 u_size;    // pixels

layout(location = 0) out vec4 f_albedo;
layout(location = 1) out vec4 f_height;

void main() {
    vec2 uv = gl_FragCoord.xy / u_size;
    float spec = 1.0;
    float h = 0.0;
    vec3 c = u_color;
#if TEXTURE_KIND == 2
    c = sylva_bark(u_color, uv, vec3(0.0), 1.0, true, spec);
    h = sylva_bark_height(uv);
#elif TEXTURE_KIND == 3
    c = sylva_leaf(u_color, uv, spec);
    h = sylva_leaf_height(uv);
#elif TEXTURE_KIND == 4
    c = sylva_grass_tiled(u_color, uv, spec);
#endif
    f_albedo = vec4(c, spec);
    f_height = vec4(h, 0.0, 0.0, 1.0);
}
