// Multi-bounce G(A, rho) from the profiles' monotone tables (docs/profiles.md §8): the shader port
// of gtsoMultiBounceTable of gtso_runtime.h, one lookup for every table. `gtbake export` writes it
// into gtbake_tables.hlsl / .glsl when a profile ships a table; tests/shader executes it against
// the C++ header.
//
// Needs before it kMultiBounceTableRho (float[]: every table's albedos, ascending, one table after
// the other) and kMultiBounceTableValues (float[]: every table's G, [row][node], one table after
// the other). A table is data: its albedos' offset rho0 and count rows in the first array, its
// values' offset g0 and node count nodes in the second (G at A = 0, 1/(nodes - 1), ..., 1).
// Linear in A between nodes (A clamped to [0, 1]) and in the albedo between rows (clamped to the
// rows).

float gtsoMultiBounceTableRow(int g0, int nodes, int row, float A) {
  float x = clamp(A, 0.0, 1.0) * float(nodes - 1);
  int i = min(int(x), nodes - 2);
  float v0 = kMultiBounceTableValues[g0 + row * nodes + i];
  return v0 + (x - float(i)) * (kMultiBounceTableValues[g0 + row * nodes + i + 1] - v0);
}

float gtsoMultiBounceTable(int rho0, int rows, int g0, int nodes, float A, float albedo) {
  int j0 = 0;
  int j1 = 0;
  float s = 0.0;
  if (albedo >= kMultiBounceTableRho[rho0 + rows - 1]) {
    j0 = rows - 1;
    j1 = j0;
  } else if (albedo > kMultiBounceTableRho[rho0]) {
    for (int j = 0; j < rows - 1; ++j) j0 = kMultiBounceTableRho[rho0 + j] < albedo ? j : j0;
    j1 = j0 + 1;
    s = (albedo - kMultiBounceTableRho[rho0 + j0]) /
        (kMultiBounceTableRho[rho0 + j1] - kMultiBounceTableRho[rho0 + j0]);
  }
  float g = gtsoMultiBounceTableRow(g0, nodes, j0, A);
  return g + s * (gtsoMultiBounceTableRow(g0, nodes, j1, A) - g);
}
