// hairkit view: the text overlay: the glyphs' set texels in Ink over a Shade backing.
#version 330 core
in vec2 vUV;

uniform sampler2D Font; // one channel: 1 where a glyph's dot is set
uniform vec4 Ink, Shade;

out vec4 FragColor;

void main()
{
    if (vUV.x < 0.0) {
        FragColor = Shade;
        return;
    }
    if (texture(Font, vUV).r < 0.5) discard;
    FragColor = Ink;
}
