#version 330 core
// Per-fragment Phong lighting of seed 004 §3.4-3.6: ambient + diffuse + specular (with a
// specular map), a directional sun with a shadow map, and point lights with attenuation.
// Variants (the renderer compiles one program per combination it meets, so that a CPU
// rasteriser such as llvmpipe, which runs both sides of a branch, pays only for what is used):
//   HAS_UV, HAS_COLORS   the mesh has uvs / vertex colours;
//   TEXTURE_KIND n       0 none, 1 image, 2 bark, 3 leaf, 4 grass;
//   LIT                  Phong lighting (else the unlit albedo);
//   SUN, SHADOWS         a directional sun, and its shadow map;
//   POINTS               point lights (u_n_points of them);
//   GROUND_FADE          blend into the sky's horizon colour with distance from u_fade_center.

#include "noise.glsl"
#include "textures.glsl"

#define MAX_POINT_LIGHTS 8
#ifndef TEXTURE_KIND
#define TEXTURE_KIND 0
#endif

in vec3 v_world;
in vec3 v_normal;
#ifdef HAS_UV
in vec2 v_uv;
#endif
#ifdef HAS_COLORS
in vec4 v_color;
#endif

uniform vec4 u_color;            // material base colour, linear RGBA
uniform float u_shininess;       // Phong exponent
uniform float u_specular;        // material specular strength
uniform bool u_double_sided;
uniform float u_alpha_cutoff;    // < 0: no alpha test
uniform float u_noise_scale;
uniform sampler2D texture_diffuse1;   // sRGB image (white 1x1 when none)
uniform sampler2D texture_specular1;  // intensity (white 1x1 when none)

uniform vec3 u_view_pos;
uniform vec3 u_view_dir;         // towards the eye, for orthographic cameras
uniform bool u_ortho;

uniform vec3 u_sun_dir;          // where the rays travel
uniform vec3 u_sun_diffuse;
uniform vec3 u_sun_ambient;
uniform vec3 u_sun_specular;
uniform mat4 u_light_view_proj;
uniform sampler2DShadow u_shadow_map;
uniform float u_shadow_texel;
uniform float u_shadow_bias;

uniform int u_n_points;
uniform vec3 u_point_pos[MAX_POINT_LIGHTS];
uniform vec3 u_point_diffuse[MAX_POINT_LIGHTS];
uniform vec3 u_point_ambient[MAX_POINT_LIGHTS];
uniform vec3 u_point_specular[MAX_POINT_LIGHTS];
uniform vec3 u_point_atten[MAX_POINT_LIGHTS];

#ifdef GROUND_FADE
uniform vec2 u_fade_center;      // world (x, z)
uniform vec2 u_fade_range;       // horizontal distances where the fade starts and ends
uniform vec3 u_horizon;          // sRGB
#endif

out vec4 f_color;

#ifdef SHADOWS
float shadow_factor(vec3 n, vec3 l) {
    vec4 lp = u_light_view_proj * vec4(v_world, 1.0);
    vec3 p = lp.xyz / lp.w * 0.5 + 0.5;
    if (p.x <= 0.0 || p.x >= 1.0 || p.y <= 0.0 || p.y >= 1.0 || p.z >= 1.0) {
        return 1.0;
    }
    float slope = sqrt(max(1.0 - pow(max(dot(n, l), 0.0), 2.0), 0.0));
    float bias = u_shadow_bias * (1.0 + 3.0 * slope);
    float lit = 0.0;
    for (int dx = -1; dx <= 1; ++dx) {
        for (int dy = -1; dy <= 1; ++dy) {
            vec2 o = vec2(float(dx), float(dy)) * u_shadow_texel;
            lit += texture(u_shadow_map, vec3(p.xy + o, p.z - bias));
        }
    }
    return lit / 9.0;
}
#endif

void main() {
#ifdef HAS_COLORS
    vec4 base = u_color * v_color;
#else
    vec4 base = u_color;
#endif
#ifdef HAS_UV
    vec2 uv = v_uv;
    bool has_uv = true;
#else
    vec2 uv = vec2(0.25, 0.5);
    bool has_uv = false;
#endif
    float spec_map = 1.0;
    vec3 albedo = base.rgb;
#if TEXTURE_KIND == 1
    vec4 t = texture(texture_diffuse1, uv);
    albedo *= pow(t.rgb, vec3(2.2));
    base.a *= t.a;
    spec_map = texture(texture_specular1, uv).r;
#elif TEXTURE_KIND == 2
    albedo = sylva_bark(albedo, uv, v_world, u_noise_scale, has_uv, spec_map);
#elif TEXTURE_KIND == 3
    albedo = sylva_leaf(albedo, uv, spec_map);
#elif TEXTURE_KIND == 4
    albedo = sylva_grass(albedo, v_world, u_noise_scale, spec_map);
#endif
    if (u_alpha_cutoff >= 0.0 && base.a < u_alpha_cutoff) {
        discard;
    }
    vec3 color = albedo;
#ifdef LIT
    vec3 n = normalize(v_normal);
    if (u_double_sided && !gl_FrontFacing) {
        n = -n;
    }
    vec3 v = u_ortho ? normalize(u_view_dir) : normalize(u_view_pos - v_world);
    vec3 spec_color = vec3(u_specular * spec_map);
    color = vec3(0.0);
#ifdef SUN
    {
        vec3 l = normalize(-u_sun_dir);
        float diff = max(dot(n, l), 0.0);
        float s = diff > 0.0 ? pow(max(dot(v, reflect(-l, n)), 0.0), u_shininess) : 0.0;
#ifdef SHADOWS
        float shade = shadow_factor(n, l);
#else
        float shade = 1.0;
#endif
        color += u_sun_ambient * albedo;
        color += shade * (diff * u_sun_diffuse * albedo + s * u_sun_specular * spec_color);
    }
#endif
#ifdef POINTS
    for (int i = 0; i < u_n_points; ++i) {
        vec3 d = u_point_pos[i] - v_world;
        float dist = length(d);
        vec3 l = d / max(dist, 1e-6);
        vec3 k = u_point_atten[i];
        float att = 1.0 / (k.x + k.y * dist + k.z * dist * dist);
        float diff = max(dot(n, l), 0.0);
        float s = diff > 0.0 ? pow(max(dot(v, reflect(-l, n)), 0.0), u_shininess) : 0.0;
        color += att * (u_point_ambient[i] * albedo + diff * u_point_diffuse[i] * albedo
                        + s * u_point_specular[i] * spec_color);
    }
#endif
#endif
    color = pow(clamp(color, 0.0, 1.0), vec3(1.0 / 2.2));
#ifdef GROUND_FADE
    float fade = smoothstep(u_fade_range.x, u_fade_range.y, length(v_world.xz - u_fade_center));
    color = mix(color, u_horizon, fade);
#endif
    f_color = vec4(color, base.a);
}
