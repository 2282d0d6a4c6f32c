// hairkit view: the linear picture onto the window, encoded to sRGB.
#version 330 core
in vec2 vUV;
uniform sampler2D Picture;
out vec4 FragColor;
vec3 srgb(vec3 c)
{
    c = clamp(c, 0.0, 1.0);
    return mix(c * 12.92, 1.055 * pow(c, vec3(1.0 / 2.4)) - 0.055, step(0.0031308, c));
}
void main() { FragColor = vec4(srgb(texture(Picture, vUV).rgb), 1.0); }
