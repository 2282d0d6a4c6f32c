// hairkit view: the CPU renderer's background, a vertical gradient (linear RGB).
#version 330 core
uniform vec3 Top, Bottom;
uniform float Height;
out vec4 FragColor;
void main()
{
    float y = Height - 0.5 - gl_FragCoord.y; // pixel row from the top
    float f = Height > 1.0 ? y / (Height - 1.0) : 0.0;
    FragColor = vec4(mix(Top, Bottom, f), 1.0);
}
