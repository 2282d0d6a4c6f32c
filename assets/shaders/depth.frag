// hairkit view: the depth passes from the light write depth only.
#version 330 core
void main() {}
