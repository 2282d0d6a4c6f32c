// hairkit view: the text overlay (viewer/gl_overlay.c), quads in pixels from the top left.
#version 330 core
layout(location = 0) in vec4 Corner; // xy: pixels from the picture's top left; zw: font texture (x < 0: the backing)

uniform vec2 Size; // the picture, pixels

out vec2 vUV;

void main()
{
    vUV = Corner.zw;
    gl_Position = vec4(Corner.x / Size.x * 2.0 - 1.0, 1.0 - Corner.y / Size.y * 2.0, 0.0, 1.0);
}
