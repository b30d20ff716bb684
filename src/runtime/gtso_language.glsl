#define GTSO_VEC3 vec3
#define GTSO_VEC4 vec4
#define GTSO_ATAN2(y, x) atan(y, x)
#define GTSO_TEXTURE sampler3D tex
#define GTSO_SAMPLE(c) textureLod(tex, c, 0.0).r
