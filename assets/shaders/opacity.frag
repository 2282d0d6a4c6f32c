// hairkit view: the opacity map (thesis section 4.1.6, as deep opacity maps): every hair
// fragment adds its opacity to the layers that end behind it (blending adds).
#version 330 core
uniform sampler2D HairDepth; // z0 of each texel, from the depth pass
uniform vec4 LayerEnd;       // end of each layer behind z0 (the last takes all beyond)
uniform float Alpha;         // a hair's opacity in one texel
out vec4 Opacity;
void main()
{
    float z0 = texelFetch(HairDepth, ivec2(gl_FragCoord.xy), 0).r;
    float d = gl_FragCoord.z - z0;
    Opacity = Alpha * vec4(d < LayerEnd.x ? 1.0 : 0.0, d < LayerEnd.y ? 1.0 : 0.0, d < LayerEnd.z ? 1.0 : 0.0, 1.0);
}
