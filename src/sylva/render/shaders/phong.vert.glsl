#version 330 core
// World-space meshes: no model matrix.  u_view_proj includes the tile's off-centre frustum.
// Variants: HAS_UV and HAS_COLORS are defined when the mesh has those attributes.
uniform mat4 u_view_proj;

in vec3 in_position;
in vec3 in_normal;
out vec3 v_world;
out vec3 v_normal;
#ifdef HAS_UV
in vec2 in_uv;
out vec2 v_uv;
#endif
#ifdef HAS_COLORS
in vec4 in_color;
out vec4 v_color;
#endif
#ifdef BILLBOARD
// seed 002's billboard flag: each leaf (a connected piece) turns about its centre
// in_pivot.xyz so that its plane normal in_axis faces the camera (in_pivot.w = 1)
in vec4 in_pivot;
in vec3 in_axis;
uniform vec3 u_view_pos;
uniform vec3 u_view_dir;  // toward the viewer
uniform bool u_ortho;

vec3 turn(vec3 d, vec3 k, float c) {
    // Rodrigues' rotation by the unnormalised axis k = n x v, cos = c
    return d * c + cross(k, d) + k * (dot(k, d) / (1.0 + c));
}
#endif

void main() {
    vec3 p = in_position;
    vec3 nrm = in_normal;
#ifdef BILLBOARD
    if (in_pivot.w > 0.5) {
        vec3 v = u_ortho ? normalize(u_view_dir) : normalize(u_view_pos - in_pivot.xyz);
        vec3 n = normalize(in_axis);
        if (dot(n, v) < 0.0) {
            n = -n;
        }
        vec3 k = cross(n, v);
        float c = dot(n, v);
        p = in_pivot.xyz + turn(p - in_pivot.xyz, k, c);
        nrm = turn(nrm, k, c);
    }
#endif
    v_world = p;
    v_normal = nrm;
#ifdef HAS_UV
    v_uv = in_uv;
#endif
#ifdef HAS_COLORS
    v_color = in_color;
#endif
    gl_Position = u_view_proj * vec4(p, 1.0);
}
