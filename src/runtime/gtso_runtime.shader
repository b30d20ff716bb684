// GTSO lookups, cone model and multi-bounce for HLSL and GLSL: the shader port of
// gtso_runtime.h (same axis maps, same half-texel remap and 4D tiles; the texture unit does the
// decode and the trilinear filter). `gtbake export` prepends the language macros and the
// constants below and writes the result as gtbake_tables.hlsl / .glsl; tests/shader compiles both
// to SPIR-V and executes them against the C++ header.
//
// Needs before it: GTSO_VEC3, GTSO_VEC4, GTSO_ATAN2(y, x), GTSO_TEXTURE (parameter declaration
// of one volume texture), GTSO_SAMPLE(coord) (its filtered value at coord), and the constants
// kGtsoPiF, kGtsoSigmaScaleF, kGtsoSigmaFloorF, kGtsoSpanFloorF, kGtsoThetaLobeScaleF,
// kGtsoThetaLobeFloorF, kGtsoThetaLinearF, kGtsoBetaLinearF (the axis constants of
// gtso_runtime.h, written by export from the same C++ constants), kGtso3DSize (float3),
// kGtso4DSize (float4 as x, y, z, w), kGtso4DTilesX (theta_o slices across texture x,
// GtsoLayout::tilesX), kGtso4DVolumeSize (float3, the 4D texture's extent), kConeApertureU and
// kMultiBounceA/B/C ({slope, intercept}
// as float2, .x = slope). GTSO_3D_LAYOUT(c) / GTSO_4D_LAYOUT(c): the swizzle taking the table
// axes (A, theta_o or beta, r_p) to texture (x, y, z) in the layout export chose (gtso_runtime.h
// GtsoLayout; e.g. (c).yzx puts theta_o and r_p in the BC4 block plane and A in depth).

// asinh(x) for x >= 0 (HLSL has no asinh).
float gtsoAsinh(float x) { return log(x + sqrt(x * x + 1.0)); }

float gtsoAlphaV(float A) {
  float a = clamp(A, 0.0, 1.0);
  return GTSO_ATAN2(sqrt(a), sqrt(1.0 - a));
}

// The span of each side of the step (gtsoSpanAbove / gtsoSpanBelow of gtso_runtime.h).
float gtsoSpanAbove(float s) {
  float d = max(0.5 * kGtsoPiF - s, 0.0);
  return sqrt(d * d + kGtsoSpanFloorF * kGtsoSpanFloorF);
}
float gtsoSpanBelow(float s) { return sqrt(s * s + kGtsoSpanFloorF * kGtsoSpanFloorF); }

// alpha_v -> t on the step-warped A axis (step s, width sigma, step texel tS).
float gtsoStepWarp(float alphaV, float s, float sigma, float tS) {
  if (alphaV >= s) {
    float span = gtsoAsinh(gtsoSpanAbove(s) / sigma);
    return tS + (1.0 - tS) * clamp(gtsoAsinh((alphaV - s) / sigma) / span, 0.0, 1.0);
  }
  return tS - tS * clamp(gtsoAsinh((s - alphaV) / sigma) / gtsoAsinh(gtsoSpanBelow(s) / sigma),
                         0.0, 1.0);
}

// The lobe scale lambda of the theta_o and beta axes.
float gtsoThetaLambda(float rp) { return kGtsoThetaLobeScaleF * rp * rp + kGtsoThetaLobeFloorF; }

// theta_o axis, refined at normal view and at grazing on the scale lambda.
float gtsoThetaWarp(float thetaO, float rp) {
  float th = clamp(thetaO, 0.0, 0.5 * kGtsoPiF);
  float lambda = gtsoThetaLambda(rp);
  float L = gtsoAsinh(0.5 * kGtsoPiF / lambda);
  float ends = (gtsoAsinh(th / lambda) - gtsoAsinh((0.5 * kGtsoPiF - th) / lambda) + L) / (2.0 * L);
  return clamp(kGtsoThetaLinearF * th / (0.5 * kGtsoPiF) + (1.0 - kGtsoThetaLinearF) * ends, 0.0,
               1.0);
}

// F(beta) of the beta axis (refined at beta = 0 on the scale lambda).
float gtsoBetaDensity(float beta, float rp) {
  float lambda = gtsoThetaLambda(rp);
  return kGtsoBetaLinearF * beta / (0.5 * kGtsoPiF) +
         (1.0 - kGtsoBetaLinearF) * gtsoAsinh(beta / lambda) / gtsoAsinh(0.5 * kGtsoPiF / lambda);
}

// 4D beta axis over [0, theta_o + pi/2], split at beta = theta_o on texel tB.
float gtsoBetaWarp(float beta, float thetaO, float rp, float tB) {
  float b = max(beta, 0.0);
  float fo = gtsoBetaDensity(thetaO, rp);
  float f = gtsoBetaDensity(b, rp);
  if (b < thetaO) return tB * f / fo;
  float fe = gtsoBetaDensity(thetaO + 0.5 * kGtsoPiF, rp);
  return clamp(tB + (1.0 - tB) * (f - fo) / (fe - fo), 0.0, 1.0);
}

float gtsoSigma(float rp) { return kGtsoSigmaScaleF * rp * rp + kGtsoSigmaFloorF; }

// Half-texel remap: t = 0 and t = 1 land on the centres of the first and last texels.
float gtsoTexelRemap(float t, float n) { return (t * (n - 1.0) + 0.5) / n; }

// 3D table-axis coordinates (A step-warped around alpha_v = theta_o, theta_o, r_p), remapped.
GTSO_VEC3 gtso3DAxisCoord(float A, float cosBeta, float rp) {
  float thetaO = acos(clamp(cosBeta, 0.0, 1.0));
  float r = clamp(rp, 0.0, 1.0);
  float tS = floor((kGtso3DSize.x - 1.0) * 0.5) / (kGtso3DSize.x - 1.0);
  float tA = gtsoStepWarp(gtsoAlphaV(A), thetaO, gtsoSigma(r), tS);
  return GTSO_VEC3(gtsoTexelRemap(tA, kGtso3DSize.x),
                     gtsoTexelRemap(gtsoThetaWarp(thetaO, r), kGtso3DSize.y),
                     gtsoTexelRemap(sqrt(r), kGtso3DSize.z));
}

// The 3D volume's texture coordinates: the table axes in the layout export chose.
GTSO_VEC3 gtso3DTexCoord(float A, float cosBeta, float rp) {
  return GTSO_3D_LAYOUT(gtso3DAxisCoord(A, cosBeta, rp));
}

// S3(A, beta, r_p), bent normal = n: one trilinear fetch.
float gtso3DSample(GTSO_TEXTURE, float A, float cosBeta, float rp) {
  return GTSO_SAMPLE(gtso3DTexCoord(A, cosBeta, rp));
}

// 4D: the texel positions t (N - 1) of the table axes (A, beta, r_p) and of the theta_o slice
// (.w), as gtso4DAxes of gtso_runtime.h maps them.
GTSO_VEC4 gtso4DAxisTexels(float A, float cosBeta, float rp, float cosThetaO) {
  float beta = acos(clamp(cosBeta, -1.0, 1.0));
  float thetaO = acos(clamp(cosThetaO, 0.0, 1.0));
  float r = clamp(rp, 0.0, 1.0);
  float tS = floor((kGtso4DSize.x - 1.0) * 0.5) / (kGtso4DSize.x - 1.0);
  float tB = floor(kGtso4DSize.y / 3.0) / (kGtso4DSize.y - 1.0);
  return GTSO_VEC4(gtsoStepWarp(gtsoAlphaV(A), beta, gtsoSigma(r), tS) * (kGtso4DSize.x - 1.0),
                   gtsoBetaWarp(beta, thetaO, r, tB) * (kGtso4DSize.y - 1.0),
                   sqrt(r) * (kGtso4DSize.z - 1.0),
                   gtsoThetaWarp(thetaO, r) * (kGtso4DSize.w - 1.0));
}

// The texture coordinate of texel position p (texture axes, in the layout) in the tile of theta_o
// slice s: the tile's first texel is (N_x (s mod kGtso4DTilesX), 0, N_z floor(s / kGtso4DTilesX)).
// Each component of p lies in [0, N - 1] (the axis maps give t in [0, 1]), i.e. between the
// centres of the tile's first and last texels, so the filter reads the tile's texels only.
GTSO_VEC3 gtso4DTileCoord(GTSO_VEC3 p, float s) {
  GTSO_VEC3 n = GTSO_4D_LAYOUT(kGtso4DSize.xyz);
  float down = floor((s + 0.5) / kGtso4DTilesX);  // + 0.5: exact under a rounded division
  GTSO_VEC3 lo = GTSO_VEC3((s - down * kGtso4DTilesX) * n.x, 0.0, down * n.z);
  return (lo + p + 0.5) / kGtso4DVolumeSize;
}

// S4(A, beta, r_p, theta_o): two trilinear fetches in the tiles of the neighbouring theta_o
// slices and a lerp.
float gtso4DSample(GTSO_TEXTURE, float A, float cosBeta, float rp, float cosThetaO) {
  GTSO_VEC4 a = gtso4DAxisTexels(A, cosBeta, rp, cosThetaO);
  float s0 = min(floor(a.w), kGtso4DSize.w - 2.0);
  GTSO_VEC3 p = GTSO_4D_LAYOUT(a.xyz);
  float f0 = GTSO_SAMPLE(gtso4DTileCoord(p, s0));
  float f1 = GTSO_SAMPLE(gtso4DTileCoord(p, s0 + 1.0));
  return f0 + (f1 - f0) * (a.w - s0);
}

// Multi-bounce G(A, rho) = a A^3 - b A^2 + c A (paper Eq. 10), unclamped, for
// constants {slope, intercept} in rho: a = a1 rho + a0, and so on.
float gtsoMultiBounce(float a1, float a0, float b1, float b0, float c1, float c0, float A,
                      float albedo) {
  float a = a1 * albedo + a0;
  float b = b1 * albedo + b0;
  float c = c1 * albedo + c0;
  return ((a * A - b) * A + c) * A;
}
// With the shipped constants kMultiBounceA/B/C.
float multiBounce(float A, float albedo) {
  return gtsoMultiBounce(kMultiBounceA.x, kMultiBounceA.y, kMultiBounceB.x, kMultiBounceB.y,
                         kMultiBounceC.x, kMultiBounceC.y, A, albedo);
}

// 1 - exp(x) for x <= 0 without cancellation near 0 (no expm1 in shaders).
float gtsoOneMinusExp(float x) { return abs(x) < 1e-3 ? -x * (1.0 + 0.5 * x) : 1.0 - exp(x); }

// Solid angle of the intersection of two spherical caps (half-angles up to pi/2, Mazonka 2012).
float gtsoCapIntersection(float alphaV, float alphaS, float beta) {
  if (beta >= alphaV + alphaS) return 0.0;
  if (beta <= abs(alphaV - alphaS)) {
    float h = sin(0.5 * min(alphaV, alphaS));
    return 4.0 * kGtsoPiF * h * h;
  }
  float c1 = cos(alphaV), c2 = cos(alphaS), cd = cos(beta);
  float s1 = sin(alphaV), s2 = sin(alphaS), sd = sin(beta);
  float t0 = acos(clamp((cd - c1 * c2) / (s1 * s2), -1.0, 1.0));
  float t1 = acos(clamp((c2 - cd * c1) / (sd * s1), -1.0, 1.0));
  float t2 = acos(clamp((c1 - cd * c2) / (sd * s2), -1.0, 1.0));
  return max(0.0, 2.0 * (kGtsoPiF - t0 - c1 * t1 - c2 * t2));
}

// Cone-to-cone specular occlusion (paper Eq. 19): cos(alpha_v) = sqrt(1 - A), cos(alpha_s) =
// u^(alpha^2/2), alpha = rp^2, axes beta apart.
float gtsoConeModel(float A, float cosBeta, float rp) {
  float alpha = rp * rp;
  float oneMinusCosS = gtsoOneMinusExp(0.5 * alpha * alpha * log(kConeApertureU));
  float alphaV = gtsoAlphaV(A);
  float beta = acos(clamp(cosBeta, -1.0, 1.0));
  if (oneMinusCosS <= 0.0) return (beta <= alphaV && A > 0.0) ? 1.0 : 0.0;  // mirror limit
  float alphaS = 2.0 * asin(sqrt(0.5 * oneMinusCosS));
  return clamp(gtsoCapIntersection(alphaV, alphaS, beta) / (2.0 * kGtsoPiF * oneMinusCosS), 0.0,
               1.0);
}

// ---- closed-form S3, no sampler (gtso_runtime.h gtsoS3ClosedForm; docs/gtso.md) ----
// Needs kGtsoS3ClosedForm (float[90]: 9 sets of 10 polynomial coefficients, fitted by
// `gtbake gtso`) and kGtsoS3ClosedFormAlphaFloorF. S = (1 - w) L(z) + w L(p_t d) in the log-odds
// u = log(A / (1 - A)) / 2 around the lobe's median u_m; exactly 0 at A = 0 and 1 at A = 1.
float gtsoLogistic(float z) {
  if (z < 0.0) {
    float e = exp(z);
    return e / (1.0 + e);
  }
  return 1.0 / (1.0 + exp(-z));
}

// cosBeta = cos theta_o = n.wr (bent normal taken as n, like gtso3DSample), rp perceptual
// roughness (alpha = rp^2).
float gtsoS3ClosedForm(float A, float cosBeta, float rp) {
  float mu = clamp(cosBeta, 0.0, 1.0);
  float r = clamp(rp, 0.0, 1.0);
  float alpha = r * r + kGtsoS3ClosedFormAlphaFloorF;
  float mu2 = mu * mu;
  float sin2 = 1.0 - mu * mu;
  float h = mu * sqrt(sin2) / alpha;  // sin(2 theta_o) / (2 alpha)
  float m = sqrt(mu);
  float q = h / (1.0 + h);
  float b[10];
  b[0] = 1.0;
  b[1] = m;
  b[2] = r;
  b[3] = m * r;
  b[4] = m * m;
  b[5] = r * r;
  b[6] = q;
  b[7] = q * m;
  b[8] = q * r;
  b[9] = q * q;
  float p[9];
  for (int s = 0; s < 9; ++s) {
    float sum = kGtsoS3ClosedForm[s * 10] * b[0];
    for (int i = 1; i < 10; ++i) sum = sum + kGtsoS3ClosedForm[s * 10 + i] * b[i];
    p[s] = sum;
  }
  if (!(A > 0.0)) return 0.0;
  if (!(A < 1.0)) return 1.0;
  float a = alpha * alpha * exp(p[0]);
  float bb = alpha * alpha * exp(p[1]);
  float median = 0.5 * log((sin2 + a * mu2) / (mu2 + bb * sin2)) + alpha * p[2];
  float lo0 = exp(p[3]), lo1 = h * exp(-p[4]);
  float hi0 = exp(p[5]), hi1 = h * exp(-p[6]);
  float d = 0.5 * log(A / (1.0 - A)) - median;
  float z = d < 0.0 ? d * sqrt(lo0 * lo0 + lo1 * lo1) : d * sqrt(hi0 * hi0 + hi1 * hi1);
  float w = gtsoLogistic(p[7]);
  return (1.0 - w) * gtsoLogistic(z) + w * gtsoLogistic(d * exp(p[8]));
}
