#include "common/image_io.h"

#include <IexBaseExc.h>
#include <ImfChannelList.h>
#include <ImfFrameBuffer.h>
#include <ImfHeader.h>
#include <ImfIO.h>
#include <ImfInputFile.h>
#include <ImfOutputFile.h>
#include <ImfStdIO.h>
#include <ImfStringAttribute.h>
#include <stb_image_write.h>
#include <sys/stat.h>

#include <ctime>

#include <algorithm>
#include <array>
#include <atomic>
#include <cmath>
#include <cstring>
#include <deque>
#include <memory>
#include <mutex>
#include <optional>
#include <sstream>
#include <string_view>
#include <unordered_map>

#include "common/atomic_file.h"
#include "common/checked_math.h"
#include "common/error.h"
#include "common/input_limits.h"
#include "common/output_set.h"
#include "common/sha256.h"

namespace gtbake {

namespace fs = std::filesystem;

const std::vector<float>& ExrImage::channel(const std::string& name,
                                            const std::string& file) const {
  const auto it = channels.find(name);
  if (it == channels.end()) throw Error(file + ": missing EXR channel '" + name + "'");
  return it->second;
}

namespace {

// Sides beyond this are refused while OpenEXR reads the header, before it allocates anything
// sized by the data window (pixels; the largest --res a sweep accepts).
constexpr int kMaxExrSide = 8192;
// More channels than this is not a gtbake EXR (a sweep writes about 40).
constexpr std::size_t kMaxExrChannels = 1024;
// Decoded float bytes per byte of file, at most: zlib's deflate cannot expand by more than
// ~1032:1, doubled for half channels read as float, with a margin. A forged data window that
// would need more memory than this ratio allows is refused before the pixels are allocated.
constexpr std::uint64_t kMaxExrExpansion = 4096;

void setExrLimits() {
  static const bool once = [] {
    Imf::Header::setMaxImageSize(kMaxExrSide, kMaxExrSide);
    Imf::Header::setMaxTileSize(kMaxExrSide, kMaxExrSide);
    return true;
  }();
  (void)once;
}

void appendToString(void* context, void* data, int size) {
  static_cast<std::string*>(context)->append(static_cast<const char*>(data),
                                             static_cast<std::size_t>(size));
}

// Walks the header's attribute list (name, type, int32 size, value) checking every size against
// the bytes actually present, before OpenEXR sees the file: OpenEXR allocates an attribute's
// value from its stated size, so a forged size would cost gigabytes. Single-part scan-line files
// only, as gtbake writes them (a forged tiled header with 1x1 tiles makes OpenEXR allocate a
// tile offset table of hundreds of megabytes).
void checkExrHeader(const std::string& bytes, const std::string& name) {
  const std::size_t size = bytes.size();
  if (size < 8 || static_cast<unsigned char>(bytes[0]) != 0x76 ||
      static_cast<unsigned char>(bytes[1]) != 0x2f ||
      static_cast<unsigned char>(bytes[2]) != 0x31 ||
      static_cast<unsigned char>(bytes[3]) != 0x01) {
    throw Error("cannot read EXR " + name + ": not an OpenEXR file");
  }
  const auto flags = static_cast<unsigned char>(bytes[5]);
  if ((flags & 0x1A) != 0) {  // bit 9 tiled, bit 11 deep data, bit 12 multi-part
    throw Error("cannot read EXR " + name +
                ": tiled, deep or multi-part files are not supported (gtbake writes scan lines)");
  }
  std::size_t at = 8;
  for (int attributes = 0;; ++attributes) {
    if (attributes > 10000) throw Error("cannot read EXR " + name + ": too many header attributes");
    if (at >= size) throw Error("cannot read EXR " + name + ": truncated header");
    if (bytes[at] == '\0') return;  // end of the header
    std::string fields[2];          // attribute name, then type name
    for (std::string& field : fields) {
      const std::size_t nul = bytes.find('\0', at);
      if (nul == std::string::npos || nul - at > 255) {
        throw Error("cannot read EXR " + name + ": malformed header attribute");
      }
      field = bytes.substr(at, nul - at);
      at = nul + 1;
    }
    const std::string& type = fields[1];
    if (size - at < 4) throw Error("cannot read EXR " + name + ": truncated header");
    std::int32_t value_size = 0;
    std::memcpy(&value_size, bytes.data() + at, 4);
    at += 4;
    if (value_size < 0 || static_cast<std::size_t>(value_size) > size - at) {
      throw Error("cannot read EXR " + name + ": a header attribute claims " +
                  std::to_string(value_size) + " bytes, more than the file holds");
    }
    // OpenEXR reads typed values by their type, not their stated size: the two must agree or
    // it would go on parsing from another offset than this walk.
    static const std::map<std::string, int> kFixedSizes = {
        {"box2i", 16}, {"box2f", 16}, {"compression", 1}, {"lineOrder", 1},
        {"float", 4},  {"double", 8}, {"int", 4},         {"v2f", 8},
        {"v2i", 8},    {"v3f", 12},   {"v3i", 12}};
    const auto fixed = kFixedSizes.find(type);
    if (fixed != kFixedSizes.end()) {
      if (value_size != fixed->second) {
        throw Error("cannot read EXR " + name + ": attribute " + fields[0] + " of type " + type +
                    " has size " + std::to_string(value_size));
      }
    } else if (type == "chlist") {
      std::size_t c = at;  // entries: name NUL, then 16 bytes; an empty name ends the list
      const std::size_t end = at + static_cast<std::size_t>(value_size);
      while (c < end && bytes[c] != '\0') {
        const std::size_t nul = bytes.find('\0', c);
        if (nul == std::string::npos || nul >= end || end - nul - 1 < 16) {
          throw Error("cannot read EXR " + name + ": malformed channel list");
        }
        c = nul + 1 + 16;
      }
      if (c + 1 != end) throw Error("cannot read EXR " + name + ": malformed channel list");
    } else if (type != "string") {
      throw Error("cannot read EXR " + name + ": unsupported header attribute type '" + type +
                  "' (gtbake writes scan-line float EXRs)");
    }
    at += static_cast<std::size_t>(value_size);
  }
}

// OpenEXR's input stream over bytes already in memory, read in place (Imf::StdISStream would
// first copy them into a std::istringstream). It behaves as StdISStream over the same bytes:
// a read past the end throws "Early end of file" and leaves the stream failed, a seek past the
// end fails it, and clear() clears that.
class MemoryIStream : public Imf::IStream {
 public:
  explicit MemoryIStream(std::string_view bytes) : Imf::IStream(""), bytes_(bytes) {}

  bool read(char c[], int n) override {
    if (failed_) throw IEX_NAMESPACE::InputExc("Unexpected end of file.");
    const std::size_t want = static_cast<std::size_t>(n);
    const std::size_t got = std::min(want, bytes_.size() - at_);
    std::memcpy(c, bytes_.data() + at_, got);
    at_ += got;
    if (got < want) {
      failed_ = true;
      std::ostringstream what;
      what << "Early end of file: read " << got << " out of " << want << " requested bytes.";
      throw IEX_NAMESPACE::InputExc(what.str());
    }
    return true;
  }
  uint64_t tellg() override { return failed_ ? UINT64_MAX : at_; }
  void seekg(uint64_t pos) override {
    if (failed_) return;
    if (pos > bytes_.size()) {
      failed_ = true;
      return;
    }
    at_ = static_cast<std::size_t>(pos);
  }
  void clear() override { failed_ = false; }

 private:
  std::string_view bytes_;
  std::size_t at_ = 0;
  bool failed_ = false;
};

}  // namespace

std::string encodeExr(int width, int height, const std::vector<ExrChannel>& channels,
                      const std::map<std::string, std::string>& attributes) {
  const size_t count = static_cast<size_t>(width) * static_cast<size_t>(height);
  for (const auto& c : channels) {
    if (c.pixels.size() != count) {
      throw Error("internal: EXR channel " + c.name + " has the wrong pixel count");
    }
  }
  Imf::StdOSStream stream;
  {
    Imf::Header header(width, height);
    header.compression() = Imf::RLE_COMPRESSION;
    for (const auto& [key, value] : attributes) {
      header.insert(key, Imf::StringAttribute(value));
    }
    Imf::FrameBuffer frame;
    for (const auto& c : channels) {
      header.channels().insert(c.name, Imf::Channel(Imf::FLOAT));
      frame.insert(c.name, Imf::Slice(Imf::FLOAT,
                                      reinterpret_cast<char*>(const_cast<float*>(c.pixels.data())),
                                      sizeof(float), sizeof(float) * static_cast<size_t>(width)));
    }
    Imf::OutputFile file(stream, header);
    file.setFrameBuffer(frame);
    file.writePixels(height);
  }  // the destructor writes the line offset table
  return stream.str();
}

void writeExr(const fs::path& path, int width, int height, const std::vector<ExrChannel>& channels,
              const std::map<std::string, std::string>& attributes) {
  std::string bytes;
  try {
    bytes = encodeExr(width, height, channels, attributes);
  } catch (const Error&) {
    throw;
  } catch (const std::exception& e) {
    throw Error("cannot write " + path.string() + ": " + e.what());
  }
  writeFileAtomically(path, bytes);
}

namespace {

// Refuses an image whose size is not `expect`'s (0 = not known).
void checkExpectedSize(int width, int height, const std::string& name, const ExrExpect& expect) {
  if ((expect.width > 0 && width != expect.width) ||
      (expect.height > 0 && height != expect.height)) {
    throw Error(name + ": size " + std::to_string(width) + "x" + std::to_string(height) +
                " does not match " + expect.source + " (" + std::to_string(expect.width) + "x" +
                std::to_string(expect.height) + ")");
  }
}

// The decoded images of the files this process read, by the SHA-256 of their bytes: in `gtbake
// all` every stage reads the sweep's EXRs again (each stage reads only files,
// docs/architecture.md), and decoding them is most of what a profile's fit costs. Identical bytes
// decode to the identical image, so a hit returns exactly what decoding would; only successful
// decodes are kept, oldest dropped first beyond kExrCacheBytes of pixels (docs/performance.md
// "Decoded images").
constexpr std::size_t kExrCacheBytes = std::size_t{1} << 30;

class DecodedExrCache {
 public:
  std::shared_ptr<const ExrImage> find(const std::string& key) {
    const std::lock_guard<std::mutex> lock(mutex_);
    const auto it = images_.find(key);
    return it == images_.end() ? nullptr : it->second;
  }
  void add(const std::string& key, std::shared_ptr<const ExrImage> image) {
    std::size_t bytes = 0;
    for (const auto& [name, pixels] : image->channels) bytes += pixels.size() * sizeof(float);
    if (bytes > kExrCacheBytes) return;
    const std::lock_guard<std::mutex> lock(mutex_);
    if (!images_.emplace(key, std::move(image)).second) return;
    order_.emplace_back(key, bytes);
    total_ += bytes;
    while (total_ > kExrCacheBytes) {
      total_ -= order_.front().second;
      images_.erase(order_.front().first);
      order_.pop_front();
    }
  }

 private:
  std::mutex mutex_;
  std::unordered_map<std::string, std::shared_ptr<const ExrImage>> images_;
  std::deque<std::pair<std::string, std::size_t>> order_;
  std::size_t total_ = 0;
};

DecodedExrCache& decodedExrCache() {
  static DecodedExrCache cache;
  return cache;
}

ExrImage decodeExrBytes(const std::string& bytes, const std::string& name,
                        const ExrExpect& expect) {
  setExrLimits();
  ExrImage image;
  checkExrHeader(bytes, name);
  try {
    MemoryIStream stream(bytes);
    Imf::InputFile file(stream);
    const Imath::Box2i window = file.header().dataWindow();
    if (window.min.x != 0 || window.min.y != 0 || window.max.x < 0 || window.max.y < 0) {
      throw Error(name + ": EXR data window must start at (0, 0)");
    }
    image.width = window.max.x + 1;
    image.height = window.max.y + 1;
    checkExpectedSize(image.width, image.height, name, expect);
    std::size_t channel_count = 0;
    for (auto it = file.header().channels().begin(); it != file.header().channels().end(); ++it) {
      ++channel_count;
    }
    if (channel_count > kMaxExrChannels) {
      throw Error(name + ": " + std::to_string(channel_count) + " EXR channels (at most " +
                  std::to_string(kMaxExrChannels) + ")");
    }
    const size_t count = static_cast<size_t>(image.width) * static_cast<size_t>(image.height);
    const std::uint64_t decoded = checkedMul(checkedMul(count, channel_count, name), 4, name);
    if (decoded > checkedMul(bytes.size() + 1, kMaxExrExpansion, name)) {
      throw Error(name + ": its data window (" + std::to_string(image.width) + "x" +
                  std::to_string(image.height) + ", " + std::to_string(channel_count) +
                  " channels) is far larger than a " + std::to_string(bytes.size()) +
                  "-byte file can hold (truncated or forged header)");
    }
    Imf::FrameBuffer frame;
    for (auto it = file.header().channels().begin(); it != file.header().channels().end(); ++it) {
      auto& pixels = image.channels[it.name()];
      pixels.assign(count, 0.0f);
      frame.insert(it.name(),
                   Imf::Slice(Imf::FLOAT, reinterpret_cast<char*>(pixels.data()), sizeof(float),
                              sizeof(float) * static_cast<size_t>(image.width)));
    }
    for (auto it = file.header().begin(); it != file.header().end(); ++it) {
      if (const auto* s = dynamic_cast<const Imf::StringAttribute*>(&it.attribute())) {
        image.attributes[it.name()] = s->value();
      }
    }
    file.setFrameBuffer(frame);
    file.readPixels(window.min.y, window.max.y);
  } catch (const Error&) {
    throw;
  } catch (const std::exception& e) {
    std::string what = e.what();
    throw Error("cannot read EXR " + name + ": " + what.substr(0, what.find('\n')));
  }
  return image;
}

// The image of `bytes`, whose SHA-256 is `key`: the cached one, or decoded and kept.
std::shared_ptr<const ExrImage> decodeExrByKey(const std::string& bytes, const std::string& key,
                                               const std::string& name, const ExrExpect& expect) {
  if (std::shared_ptr<const ExrImage> known = decodedExrCache().find(key)) {
    checkExpectedSize(known->width, known->height, name, expect);
    return known;
  }
  auto image = std::make_shared<const ExrImage>(decodeExrBytes(bytes, name, expect));
  decodedExrCache().add(key, image);
  return image;
}

// What lstat says of a regular file that changes whenever its bytes do: a write or truncation
// sets the modification and status-change times to the moment of the change, a replacement
// (rename, as every gtbake output) brings another inode, and the status-change time cannot be set
// back (touch sets only the others).
struct FileIdentity {
  dev_t device = 0;
  ino_t inode = 0;
  off_t size = 0;
  timespec modified{}, changed{};
};

bool operator==(const timespec& a, const timespec& b) {
  return a.tv_sec == b.tv_sec && a.tv_nsec == b.tv_nsec;
}
bool operator==(const FileIdentity& a, const FileIdentity& b) {
  return a.device == b.device && a.inode == b.inode && a.size == b.size &&
         a.modified == b.modified && a.changed == b.changed;
}

// The identity of `path` if it is a regular file (not a symlink); nothing otherwise.
std::optional<FileIdentity> identityOf(const fs::path& path) {
  struct stat st {};
  if (::lstat(path.c_str(), &st) != 0 || !S_ISREG(st.st_mode)) return std::nullopt;
  return FileIdentity{st.st_dev, st.st_ino, st.st_size, st.st_mtim, st.st_ctim};
}

double realtimeSeconds() {
  timespec now{};
  ::clock_gettime(CLOCK_REALTIME, &now);
  return static_cast<double>(now.tv_sec) + 1e-9 * static_cast<double>(now.tv_nsec);
}

// A file last changed this long before a read began cannot be changed again with the same
// times: a later change stamps a later time, even on a clock as coarse as a file system's.
constexpr double kSettledSeconds = 1.0;

// The output-set files this process read and verified, by path: their identity then and the
// verified SHA-256. In `gtbake all` each sweep EXR is read by about 18 stages; a file whose
// identity is unchanged since it was verified has the same bytes, so its image comes from the
// decoded cache without reading or hashing it again (docs/performance.md "Decoded images").
class VerifiedFiles {
 public:
  bool unchanged(const std::string& path, const FileIdentity& now, const std::string& sha) {
    const std::lock_guard<std::mutex> lock(mutex_);
    const auto it = files_.find(path);
    return it != files_.end() && it->second.first == now && it->second.second == sha;
  }
  void add(const std::string& path, const FileIdentity& identity, const std::string& sha) {
    const std::lock_guard<std::mutex> lock(mutex_);
    files_[path] = {identity, sha};
  }

 private:
  std::mutex mutex_;
  std::unordered_map<std::string, std::pair<FileIdentity, std::string>> files_;
};

VerifiedFiles& verifiedFiles() {
  static VerifiedFiles files;
  return files;
}

std::atomic<std::size_t> exr_reads{0}, exr_unchanged{0};

}  // namespace

ExrReadCounts exrReadCounts() {
  return {exr_reads.load(), exr_unchanged.load()};
}

ExrImage decodeExr(const std::string& bytes, const std::string& name, const ExrExpect& expect) {
  return *decodeExrByKey(bytes, sha256Hex(bytes), name, expect);
}

std::shared_ptr<const ExrImage> readVerifiedExr(const OutputManifest& manifest,
                                                const std::string& file, const std::string& name,
                                                const ExrExpect& expect) {
  const OutputFile* entry = manifest.find(file);
  const fs::path path = manifest.dir / file;
  const double began = realtimeSeconds();
  const std::optional<FileIdentity> before = identityOf(path);
  if (entry && before && verifiedFiles().unchanged(path.string(), *before, entry->sha256)) {
    if (std::shared_ptr<const ExrImage> known = decodedExrCache().find(entry->sha256)) {
      checkExpectedSize(known->width, known->height, name, expect);
      ++exr_unchanged;
      return known;
    }
  }
  const std::string bytes = manifest.readVerified(file);
  ++exr_reads;
  // readVerified returned, so `file` has an entry and the bytes' SHA-256 is exactly its; they are
  // the file's if nothing changed it while they were read.
  const std::string& sha = entry->sha256;
  const std::optional<FileIdentity> after = identityOf(path);
  if (before && after && *before == *after) {
    const double changed = static_cast<double>(after->changed.tv_sec) +
                           1e-9 * static_cast<double>(after->changed.tv_nsec);
    if (changed < began - kSettledSeconds) verifiedFiles().add(path.string(), *after, sha);
  }
  return decodeExrByKey(bytes, sha, name, expect);
}

ExrImage readExr(const fs::path& path, const ExrExpect& expect) {
  return decodeExr(readRegularFile(path), path.string(), expect);
}

std::string encodePng(int width, int height, int components,
                      const std::vector<std::uint8_t>& pixels) {
  if (pixels.size() !=
      static_cast<size_t>(width) * static_cast<size_t>(height) * static_cast<size_t>(components)) {
    throw Error("internal: PNG has the wrong pixel count");
  }
  std::string bytes;
  if (stbi_write_png_to_func(appendToString, &bytes, width, height, components, pixels.data(),
                             width * components) == 0) {
    throw Error("internal: PNG encoding failed");
  }
  return bytes;
}

void writePng(const fs::path& path, int width, int height, int components,
              const std::vector<std::uint8_t>& pixels) {
  writeFileAtomically(path, encodePng(width, height, components, pixels));
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
