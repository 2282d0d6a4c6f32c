// hairkit view: the head's fragment shader: Lambert, shadowed by the head's depth map
// and the hair's opacity map (the hair's shadow on the skin).
#version 330 core
in vec3 vNormal;
in vec4 vShadowCoord;

uniform vec3 LightDirection;
uniform vec3 SkinColor;        // linear
uniform float Ambient;
uniform int Shadows;
uniform sampler2D HairDepth;
uniform sampler2D OpacityMap;
uniform sampler2DShadow HeadDepth;
uniform float ScatterFloor;

out vec4 FragColor;

float light_reaching(vec4 sc)
{
    if (Shadows == 0) return 1.0;
    vec3 s = sc.xyz / sc.w;
    if (any(lessThan(s.xy, vec2(0.0))) || any(greaterThan(s.xy, vec2(1.0)))) return 1.0;
    float head = texture(HeadDepth, vec3(s.xy, s.z - 0.004));
    float z0 = texture(HairDepth, s.xy).r;
    float omega = s.z > z0 ? texture(OpacityMap, s.xy).a : 0.0;
    return head * (ScatterFloor + (1.0 - ScatterFloor) * exp(-omega));
}

void main()
{
    vec3 n = normalize(vNormal);
    float lambert = max(dot(n, LightDirection), 0.0);
    vec3 color = SkinColor * (Ambient + lambert * light_reaching(vShadowCoord));
    FragColor = vec4(color, 1.0);
}
