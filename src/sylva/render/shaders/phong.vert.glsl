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

void main() {
    v_world = in_position;
    v_normal = in_normal;
#ifdef HAS_UV
    v_uv = in_uv;
#endif
#ifdef HAS_COLORS
    v_color = in_color;
#endif
    gl_Position = u_view_proj * vec4(in_position, 1.0);
}
