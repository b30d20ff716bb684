// Build-time helper: writes the export fixture into argv[1] and runs `gtbake encode` and
// `gtbake export` on it, so that header_consumer_test.cpp can #include the generated
// gtbake_tables.h.
#include <cstdio>
#include <filesystem>

#include "encode/encode_command.h"
#include "export/export_command.h"
#include "export_fixture.h"

int main(int argc, char** argv) {
  if (argc != 2) {
    std::fprintf(stderr, "usage: export_fixture_gen DIR\n");
    return 2;
  }
  const std::filesystem::path dir = argv[1];
  gtbake::test::writeFixture(dir);
  gtbake::EncodeOptions encode;
  encode.gtso = dir / "gtso";
  encode.out = dir / "out";
  encode.progress = false;
  encode.force_layout_3d = gtbake::test::kFixtureLayout3D;
  encode.force_layout_4d = gtbake::test::kFixtureLayout4D;
  encode.layout_lobes = 16;
  encode.atlas_max_extent = gtbake::test::kFixtureAtlasMaxExtent;  // a tiled 4D atlas
  gtbake::runEncode(encode);
  gtbake::ExportOptions options;
  options.fit = dir / "fit.json";
  options.gtso = dir / "gtso";
  options.out = dir / "out";
  options.command_line = "export_fixture_gen (test fixture)";
  for (int k = 0; k < 2; ++k) {
    gtbake::test::writeProfileFixture(dir / "profiles", gtbake::test::kFixtureProfiles[k], k);
  }
  options.profiles = dir / "profiles";
  gtbake::runExport(options);
  return 0;
}
