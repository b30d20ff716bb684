#include "common/image_io.h"

#include <ImfChannelList.h>
#include <ImfFrameBuffer.h>
#include <ImfHeader.h>
#include <ImfInputFile.h>
#include <ImfOutputFile.h>
#include <ImfStringAttribute.h>
#include <stb_image_write.h>

#include <algorithm>
#include <array>
#include <cmath>

#include "common/atomic_file.h"
#include "common/error.h"

namespace gtbake {

namespace fs = std::filesystem;

const std::vector<float>& ExrImage::channel(const std::string& name,
                                            const std::string& file) const {
  const auto it = channels.find(name);
  if (it == channels.end()) throw Error(file + ": missing EXR channel '" + name + "'");
  return it->second;
}

void writeExr(const fs::path& path, int width, int height, const std::vector<ExrChannel>& channels,
              const std::map<std::string, std::string>& attributes) {
  const size_t count = static_cast<size_t>(width) * static_cast<size_t>(height);
  for (const auto& c : channels) {
    if (c.pixels.size() != count) {
      throw Error("internal: EXR channel " + c.name + " has the wrong pixel count");
    }
  }
  writeAtomically(path, [&](const fs::path& tmp) {
    try {
      Imf::Header header(width, height);
      header.compression() = Imf::ZIP_COMPRESSION;
      for (const auto& [key, value] : attributes) {
        header.insert(key, Imf::StringAttribute(value));
      }
      Imf::FrameBuffer frame;
      for (const auto& c : channels) {
        header.channels().insert(c.name, Imf::Channel(Imf::FLOAT));
        frame.insert(
            c.name,
            Imf::Slice(Imf::FLOAT, reinterpret_cast<char*>(const_cast<float*>(c.pixels.data())),
                       sizeof(float), sizeof(float) * static_cast<size_t>(width)));
      }
      Imf::OutputFile file(tmp.c_str(), header);
      file.setFrameBuffer(frame);
      file.writePixels(height);
    } catch (const std::exception& e) {
      throw Error("cannot write " + path.string() + ": " + e.what());
    }
  });
}

ExrImage readExr(const fs::path& path) {
  std::error_code ec;
  if (!fs::is_regular_file(path, ec)) throw Error("no such file: " + path.string());
  ExrImage image;
  try {
    Imf::InputFile file(path.c_str());
    const Imath::Box2i window = file.header().dataWindow();
    image.width = window.max.x - window.min.x + 1;
    image.height = window.max.y - window.min.y + 1;
    const size_t count = static_cast<size_t>(image.width) * static_cast<size_t>(image.height);
    Imf::FrameBuffer frame;
    for (auto it = file.header().channels().begin(); it != file.header().channels().end(); ++it) {
      auto& pixels = image.channels[it.name()];
      pixels.assign(count, 0.0f);
      char* base = reinterpret_cast<char*>(pixels.data()) -
                   (static_cast<ptrdiff_t>(window.min.x) +
                    static_cast<ptrdiff_t>(window.min.y) * image.width) *
                       static_cast<ptrdiff_t>(sizeof(float));
      frame.insert(it.name(), Imf::Slice(Imf::FLOAT, base, sizeof(float),
                                         sizeof(float) * static_cast<size_t>(image.width)));
    }
    for (auto it = file.header().begin(); it != file.header().end(); ++it) {
      if (const auto* s = dynamic_cast<const Imf::StringAttribute*>(&it.attribute())) {
        image.attributes[it.name()] = s->value();
      }
    }
    file.setFrameBuffer(frame);
    file.readPixels(window.min.y, window.max.y);
  } catch (const std::exception& e) {
    throw Error("cannot read EXR " + path.string() + ": " + e.what());
  }
  return image;
}

void writePng(const fs::path& path, int width, int height, int components,
              const std::vector<std::uint8_t>& pixels) {
  if (pixels.size() !=
      static_cast<size_t>(width) * static_cast<size_t>(height) * static_cast<size_t>(components)) {
    throw Error("internal: PNG " + path.string() + " has the wrong pixel count");
  }
  writeAtomically(path, [&](const fs::path& tmp) {
    if (stbi_write_png(tmp.c_str(), width, height, components, pixels.data(), width * components) ==
        0) {
      throw Error("cannot write " + path.string());
    }
  });
}

std::vector<std::uint8_t> toGray8(const std::vector<float>& values, float lo, float hi) {
  std::vector<std::uint8_t> out(values.size());
  const float scale = hi > lo ? 1.0f / (hi - lo) : 0.0f;
  std::transform(values.begin(), values.end(), out.begin(), [&](float v) {
    if (std::isnan(v)) return std::uint8_t{0};
    const float t = std::clamp((v - lo) * scale, 0.0f, 1.0f);
    return static_cast<std::uint8_t>(std::lround(t * 255.0f));
  });
  return out;
}

std::vector<std::uint8_t> toViridis8(const std::vector<float>& values, float lo, float hi) {
  // Nine control points of matplotlib's viridis (sRGB 0..255), interpolated linearly.
  static constexpr std::array<std::array<float, 3>, 9> kRamp = {{{68, 1, 84},
                                                                 {71, 44, 122},
                                                                 {59, 81, 139},
                                                                 {44, 113, 142},
                                                                 {33, 144, 141},
                                                                 {39, 173, 129},
                                                                 {92, 200, 99},
                                                                 {170, 220, 50},
                                                                 {253, 231, 37}}};
  std::vector<std::uint8_t> out(values.size() * 3);
  const float scale = hi > lo ? 1.0f / (hi - lo) : 0.0f;
  for (size_t i = 0; i < values.size(); ++i) {
    const float v = values[i];
    const float t = std::isnan(v) ? 0.0f : std::clamp((v - lo) * scale, 0.0f, 1.0f);
    const float x = t * static_cast<float>(kRamp.size() - 1);
    const size_t k = std::min(static_cast<size_t>(x), kRamp.size() - 2);
    const float f = x - static_cast<float>(k);
    for (size_t c = 0; c < 3; ++c) {
      const float value = kRamp[k][c] * (1.0f - f) + kRamp[k + 1][c] * f;
      out[3 * i + c] = static_cast<std::uint8_t>(std::lround(value));
    }
  }
  return out;
}

}  // namespace gtbake
