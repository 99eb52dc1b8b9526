#version 330 core
// The sky behind 3D views: colour by the elevation of the ray through each pixel.
// u_sky_rays maps the tile's (x_ndc, y_ndc, 1) to a world direction, so tiles (off-centre
// frustums) see one continuous sky.  Colours are sRGB, written as they are.
in vec2 v_ndc;

uniform mat3 u_sky_rays;
uniform vec3 u_zenith;
uniform vec3 u_horizon;
uniform float u_sky_exponent;

out vec4 f_color;

void main() {
    vec3 d = normalize(u_sky_rays * vec3(v_ndc, 1.0));
    // a power curve that leaves the horizon with a finite slope (no bright line along it)
    float t = 1.0 - pow(1.0 - clamp(d.y, 0.0, 1.0), u_sky_exponent);
    f_color = vec4(mix(u_horizon, u_zenith, t), 1.0);
}
