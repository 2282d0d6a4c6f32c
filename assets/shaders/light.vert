// hairkit view: hair and head seen from the light (the opacity shadow maps' passes).
#version 330 core
layout(location = 0) in vec3 Position;
uniform mat4 LightMatrix; // world -> [0, 1]^3
void main()
{
    vec4 s = LightMatrix * vec4(Position, 1.0);
    gl_Position = vec4(s.xyz * 2.0 - 1.0, 1.0);
}
