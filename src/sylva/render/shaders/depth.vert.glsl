#version 330 core
// Shadow-map pass: positions only, seen from the sun.
uniform mat4 u_light_view_proj;
in vec3 in_position;

void main() {
    gl_Position = u_light_view_proj * vec4(in_position, 1.0);
}
