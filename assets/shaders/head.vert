// hairkit view: the head's vertex shader (thesis 004 Appendix A, Lambert).
#version 330 core
layout(location = 0) in vec3 Position;
layout(location = 1) in vec3 Normal;

uniform mat4 ViewMatrix;
uniform mat4 ProjectionMatrix;
uniform mat4 LightMatrix;

out vec3 vNormal;
out vec4 vShadowCoord;

void main()
{
    vNormal = Normal;
    vShadowCoord = LightMatrix * vec4(Position, 1.0);
    gl_Position = ProjectionMatrix * ViewMatrix * vec4(Position, 1.0);
}
