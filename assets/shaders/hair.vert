// hairkit view: the hair's vertex shader (thesis 004 Appendix A, in GLSL 3.30 core).
// Inputs: Position (world, metres), Tangent (world, unit). docs/viewer.md lists the uniforms.
#version 330 core
layout(location = 0) in vec3 Position;
layout(location = 1) in vec3 Tangent;

uniform mat4 ViewMatrix;       // world -> eye
uniform mat4 ProjectionMatrix; // eye -> clip
uniform mat4 LightMatrix;      // world -> the light's maps: xy texture coordinates, z depth, all in [0, 1]
uniform vec3 EyePosition;      // world
uniform float Focal;           // pixels per metre at eye depth 1
uniform float Thickness;       // strand diameter (metres)

out vec3 vTangent;
out vec3 vEye;
out vec4 vShadowCoord;
out float vCoverage;

void main()
{
    vec4 eye = ViewMatrix * vec4(Position, 1.0);
    vTangent = Tangent;
    vEye = EyePosition - Position;
    vShadowCoord = LightMatrix * vec4(Position, 1.0);
    // A hair is a fraction of a pixel wide: drawn one pixel wide with that opacity.
    vCoverage = clamp(Thickness * Focal / max(-eye.z, 1e-4), 0.0, 1.0);
    gl_Position = ProjectionMatrix * eye;
}
