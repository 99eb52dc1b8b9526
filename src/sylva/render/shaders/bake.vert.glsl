#version 330 core
// A full-screen quad for baking procedural textures over the unit square of uv.
in vec2 in_position;
void main() {
    gl_Position = vec4(in_position, 0.0, 1.0);
}
