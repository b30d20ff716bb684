#define GTSO_VEC3 float3
#define GTSO_VEC4 float4
#define GTSO_ATAN2(y, x) atan2(y, x)
#define GTSO_TEXTURE Texture3D<float> tex, SamplerState linearClamp
#define GTSO_SAMPLE(c) tex.SampleLevel(linearClamp, c, 0.0)
