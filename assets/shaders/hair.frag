// hairkit view: the hair's fragment shader. Kajiya-Kay (thesis 004 section 4.1.5) or an
// approximate Marschner, shadowed by the opacity shadow maps (section 4.1.6) and the head's
// depth map. Colours are linear; the picture is encoded to sRGB when shown.
#version 330 core
in vec3 vTangent;
in vec3 vEye;
in vec4 vShadowCoord;
in float vCoverage;

uniform vec3 LightDirection;   // world, unit, towards the light
uniform vec3 AColor, DColor, SColor; // the visuality file's colours (linear)
uniform float Glossiness;
uniform float Ambient;         // 0.2: the thesis's ambient light
uniform int Shading;           // 0 Kajiya-Kay, 1 Marschner
uniform int Shadows;           // 0: no shadows
uniform sampler2D HairDepth;   // the light's depth of the first hair (z0)
uniform sampler2D OpacityMap;  // opacity accumulated to the end of layers 1..4 (r, g, b, a)
uniform sampler2DShadow HeadDepth; // the head's depth from the light
uniform vec4 LayerEnd;         // end of each layer behind z0, in map depth units
uniform float ScatterFloor;    // light that reaches the deepest hair (0.25)
uniform float Opacity;         // multiplies the coverage

out vec4 FragColor;

float opacity_before(vec3 s)
{
    float z0 = texture(HairDepth, s.xy).r;
    vec4 o = texture(OpacityMap, s.xy);
    float d = s.z - z0;
    if (d <= 0.0) return 0.0;
    // Linear within each layer (the thesis's mixer), the fourth layer tested with zi.w.
    if (d < LayerEnd.x) return mix(0.0, o.r, d / LayerEnd.x);
    if (d < LayerEnd.y) return mix(o.r, o.g, (d - LayerEnd.x) / (LayerEnd.y - LayerEnd.x));
    if (d < LayerEnd.z) return mix(o.g, o.b, (d - LayerEnd.y) / (LayerEnd.z - LayerEnd.y));
    if (d < LayerEnd.w) return mix(o.b, o.a, (d - LayerEnd.z) / (LayerEnd.w - LayerEnd.z));
    return o.a;
}

float light_reaching(vec4 sc)
{
    if (Shadows == 0) return 1.0;
    vec3 s = sc.xyz / sc.w;
    if (any(lessThan(s.xy, vec2(0.0))) || any(greaterThan(s.xy, vec2(1.0)))) return 1.0;
    float head = texture(HeadDepth, vec3(s.xy, s.z - 0.004));
    return head * (ScatterFloor + (1.0 - ScatterFloor) * exp(-opacity_before(s)));
}

vec3 kajiya_kay(vec3 t, vec3 l, vec3 e)
{
    float tl = dot(t, l), te = dot(t, e);
    float sin_tl = sqrt(max(0.0, 1.0 - tl * tl)), sin_te = sqrt(max(0.0, 1.0 - te * te));
    float cone = sin_tl * sin_te - tl * te; // the mirror cone of Kajiya & Kay
    float spec = cone > 0.0 ? pow(cone, Glossiness) : 0.0;
    return DColor * sin_tl + SColor * spec;
}

// Marschner et al. 2003, reduced to its longitudinal lobes: R shifted by -2 alpha, TT
// by alpha, TRT by 3 alpha (alpha = -3 degrees), Gaussian widths beta, 2 beta, ... and
// constant azimuthal terms, plus Kajiya-Kay's diffuse term as the CPU renderer adds.
float gauss(float b, float x) { return exp(-x * x / (2.0 * b * b)) / (b * 2.5066283); }
vec3 marschner(vec3 t, vec3 l, vec3 e)
{
    float si = clamp(dot(t, l), -1.0, 1.0), so = clamp(dot(t, e), -1.0, 1.0);
    float th = 0.5 * (asin(si) + asin(so));
    float td = 0.5 * (asin(so) - asin(si));
    float a = radians(-3.0), b = radians(8.0);
    float c2 = max(cos(td) * cos(td), 0.2);
    vec3 r = SColor * gauss(b, th - 2.0 * a) * 0.25;
    vec3 tt = DColor * gauss(0.5 * b, th + a) * 0.5;
    vec3 trt = DColor * SColor * gauss(2.0 * b, th + 3.0 * a) * 0.5;
    float sin_tl = sqrt(max(0.0, 1.0 - si * si));
    return DColor * sin_tl + (r + tt + trt) / c2 * 0.15;
}

void main()
{
    vec3 t = normalize(vTangent), l = LightDirection, e = normalize(vEye);
    vec3 lit = Shading == 1 ? marschner(t, l, e) : kajiya_kay(t, l, e);
    vec3 color = Ambient * AColor + lit * light_reaching(vShadowCoord);
    FragColor = vec4(color, clamp(vCoverage * Opacity, 0.0, 1.0));
}
