// hairkit view: outlines (the collision shapes) in one colour.
#version 330 core
layout(location = 0) in vec3 Position;

uniform mat4 ViewMatrix;
uniform mat4 ProjectionMatrix;

void main() { gl_Position = ProjectionMatrix * ViewMatrix * vec4(Position, 1.0); }
