#version 330 core
// Depth is all the shadow pass needs; the colour output is unused.
out vec4 f_color;

void main() {
    f_color = vec4(1.0);
}
