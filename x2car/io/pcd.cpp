#include "x2car/io/pcd.hpp"

#include <fmt/format.h>
#include <liblzf/lzf.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <limits>
#include <optional>
#include <vector>

#include "x2car/core/error.hpp"
#include "x2car/io/pcd_header.hpp"
#include "x2car/io/text_lines.hpp"

namespace x2car::io {
namespace {

using detail::DataKind;
using detail::PcdField;
using detail::PcdHeader;

// ---- writing -------------------------------------------------------------------------------

constexpr std::size_t kPcdPointBytes = 4 * 4 + 2 + 4;  // x y z intensity ring t, packed

std::string pcd_header(std::size_t points, std::string_view data) {
  return fmt::format(
      "# .PCD v0.7 - Point Cloud Data file format\n"
      "VERSION 0.7\n"
      "FIELDS x y z intensity ring t\n"
      "SIZE 4 4 4 4 2 4\n"
      "TYPE F F F F U F\n"
      "COUNT 1 1 1 1 1 1\n"
      "WIDTH {0}\n"
      "HEIGHT 1\n"
      "VIEWPOINT 0 0 0 1 0 0 0\n"
      "POINTS {0}\n"
      "DATA {1}\n",
      points, data);
}

template <typename T>
char* put(char* out, T value) {
  std::memcpy(out, &value, sizeof(T));
  return out + sizeof(T);
}

void append_binary(const PointCloud& cloud, std::string& bytes) {
  const std::size_t start = bytes.size();
  bytes.resize(start + cloud.points.size() * kPcdPointBytes);
  char* out = bytes.data() + start;
  for (const LidarPoint& p : cloud.points) {
    out = put(out, p.x);
    out = put(out, p.y);
    out = put(out, p.z);
    out = put(out, p.intensity);
    out = put(out, p.ring);
    out = put(out, p.t);
  }
}

void append_ascii(const PointCloud& cloud, std::string& bytes) {
  auto out = std::back_inserter(bytes);
  for (const LidarPoint& p : cloud.points) {
    fmt::format_to(out, "{} {} {} {} {} {}\n", p.x, p.y, p.z, p.intensity, p.ring, p.t);
  }
}

// binary_compressed: the fields one after the other (all x, then all y, ...), LZF-compressed,
// after two uint32: compressed and uncompressed size [bytes].
void append_compressed(const PointCloud& cloud, std::string& bytes) {
  const std::size_t n = cloud.points.size();
  std::string fields(n * kPcdPointBytes, '\0');
  char* out = fields.data();
  for (const LidarPoint& p : cloud.points) out = put(out, p.x);
  for (const LidarPoint& p : cloud.points) out = put(out, p.y);
  for (const LidarPoint& p : cloud.points) out = put(out, p.z);
  for (const LidarPoint& p : cloud.points) out = put(out, p.intensity);
  for (const LidarPoint& p : cloud.points) out = put(out, p.ring);
  for (const LidarPoint& p : cloud.points) out = put(out, p.t);
  if (fields.size() > std::numeric_limits<std::uint32_t>::max() / 2) {
    throw std::length_error("pcd: too many points for binary_compressed");
  }
  // LZF never grows its input by more than 1/16 plus a few bytes.
  std::string compressed(fields.size() + fields.size() / 16 + 64, '\0');
  const auto compressed_size =
      fields.empty() ? 0u
                     : lzf_compress(fields.data(), static_cast<unsigned>(fields.size()),
                                    compressed.data(), static_cast<unsigned>(compressed.size()));
  if (compressed_size == 0 && !fields.empty())
    throw std::runtime_error("pcd: LZF compression failed");
  std::array<char, 8> sizes{};
  put(put(sizes.data(), static_cast<std::uint32_t>(compressed_size)),
      static_cast<std::uint32_t>(fields.size()));
  bytes.append(sizes.data(), sizes.size());
  bytes.append(compressed.data(), compressed_size);
}

// ---- reading: data -------------------------------------------------------------------------

// Calls store(i, value) for the values of one binary field, value i at first + i * stride. The
// switch on the field's type sits outside the loop, so each loop is a plain typed copy.
template <typename T, typename Store>
void decode_typed(const char* first, std::size_t stride, std::size_t n, Store& store) {
  for (std::size_t i = 0; i < n; ++i) {
    T value;
    std::memcpy(&value, first + i * stride, sizeof(T));
    store(i, static_cast<double>(value));
  }
}

template <typename Store>
void decode_column(const char* first, std::size_t stride, std::size_t n, const PcdField& field,
                   Store store) {
  switch (field.type) {
    case 'F':
      return field.size == 4 ? decode_typed<float>(first, stride, n, store)
                             : decode_typed<double>(first, stride, n, store);
    case 'U':
      switch (field.size) {
        case 1:
          return decode_typed<std::uint8_t>(first, stride, n, store);
        case 2:
          return decode_typed<std::uint16_t>(first, stride, n, store);
        case 4:
          return decode_typed<std::uint32_t>(first, stride, n, store);
        default:
          return decode_typed<std::uint64_t>(first, stride, n, store);
      }
    default:
      switch (field.size) {
        case 1:
          return decode_typed<std::int8_t>(first, stride, n, store);
        case 2:
          return decode_typed<std::int16_t>(first, stride, n, store);
        case 4:
          return decode_typed<std::int32_t>(first, stride, n, store);
        default:
          return decode_typed<std::int64_t>(first, stride, n, store);
      }
  }
}

// The fields the reader uses, as indices into PcdHeader::fields.
struct UsedFields {
  std::array<std::size_t, 3> xyz{};
  std::optional<std::size_t> intensity, ring, time;
};

UsedFields used_fields(const PcdHeader& header, const std::string& file) {
  auto find = [&](std::initializer_list<std::string_view> names) -> std::optional<std::size_t> {
    for (std::size_t i = 0; i < header.fields.size(); ++i) {
      for (const auto name : names) {
        if (header.fields[i].name == name) return i;
      }
    }
    return std::nullopt;
  };
  UsedFields used;
  const std::array<std::string_view, 3> axes = {"x", "y", "z"};
  for (std::size_t a = 0; a < 3; ++a) {
    const auto index = find({axes[a]});
    if (!index) {
      throw InputError(file, header.fields_line, "FIELDS", fmt::format("no field '{}'", axes[a]));
    }
    used.xyz[a] = *index;
  }
  used.intensity = find({"intensity", "i"});
  used.ring = find({"ring"});
  used.time = find({"t", "time", "timestamp"});
  for (const auto index : {std::optional(used.xyz[0]), std::optional(used.xyz[1]),
                           std::optional(used.xyz[2]), used.intensity, used.ring, used.time}) {
    if (index && header.fields[*index].count != 1) {
      throw InputError(file, header.count_line, "COUNT",
                       fmt::format("field '{}' has COUNT {}; x2car reads COUNT 1 only",
                                   header.fields[*index].name, header.fields[*index].count));
    }
  }
  return used;
}

// Decodes the data section straight into the cloud's points; times go through a double column
// first, because an absolute stamp (1e9 s) loses its sub-millisecond part in a float.
class DataReader {
 public:
  DataReader(std::string_view bytes, const PcdHeader& header, const UsedFields& used,
             const std::string& file)
      : bytes_(bytes), header_(header), used_(used), file_(file) {}

  PointCloud read() {
    const std::size_t n = header_.points;
    // Before anything is allocated for them: a header may claim far more points than the file
    // holds (a truncated file, or a corrupt POINTS), and n points cost 24 bytes each in memory.
    check_points_fit();
    cloud_.points.resize(n);
    cloud_.has_intensity = used_.intensity.has_value();
    cloud_.has_ring = used_.ring.has_value();
    cloud_.has_time = used_.time.has_value();
    if (used_.time) time_.resize(n);
    switch (header_.data) {
      case DataKind::kAscii:
        read_ascii();
        break;
      case DataKind::kBinary:
        read_binary();
        break;
      case DataKind::kBinaryCompressed:
        read_compressed();
        break;
    }
    if (used_.time) set_times();
    return std::move(cloud_);
  }

 private:
  // Calls decode(field index, store) for every used field, store(i, value) keeping value i.
  template <typename Decode>
  void for_used(Decode decode) {
    std::vector<LidarPoint>& points = cloud_.points;
    decode(used_.xyz[0], [&](std::size_t i, double v) { points[i].x = static_cast<float>(v); });
    decode(used_.xyz[1], [&](std::size_t i, double v) { points[i].y = static_cast<float>(v); });
    decode(used_.xyz[2], [&](std::size_t i, double v) { points[i].z = static_cast<float>(v); });
    if (used_.intensity) {
      decode(*used_.intensity,
             [&](std::size_t i, double v) { points[i].intensity = static_cast<float>(v); });
    }
    if (used_.ring) {
      decode(*used_.ring, [&](std::size_t i, double v) {
        if (!(v >= 0.0 && v <= 65535.0 && v == std::floor(v))) bad_ring(i, v);
        points[i].ring = static_cast<std::uint16_t>(v);
      });
    }
    if (used_.time) decode(*used_.time, [&](std::size_t i, double v) { time_[i] = v; });
  }

  [[noreturn]] void bad_ring(std::size_t point, double ring) const {
    throw InputError(file_, header_.data_line, "ring",
                     fmt::format("point {}: ring {} is not an integer in [0, 65535]", point, ring));
  }

  [[noreturn]] void truncated(std::size_t available_bytes, std::size_t needed_points) const {
    throw InputError(
        file_, header_.data_line, "DATA",
        fmt::format("the data is truncated: {} bytes hold {} complete points of {} "
                    "bytes; POINTS is {}",
                    available_bytes,
                    header_.point_bytes == 0 ? 0 : available_bytes / header_.point_bytes,
                    header_.point_bytes, needed_points));
  }

  // Throws unless the data section can hold header_.points points. Sizes are compared by division,
  // so a huge POINTS cannot wrap a product around.
  void check_points_fit() const {
    const std::string_view data = bytes_.substr(header_.data_offset);
    const std::size_t n = header_.points;
    switch (header_.data) {
      case DataKind::kBinary:
        if (header_.point_bytes > 0 && n > data.size() / header_.point_bytes) {
          truncated(data.size(), n);
        }
        return;
      case DataKind::kBinaryCompressed:
        // The unpacked size is a uint32: more points than it can describe are corrupt.
        if (header_.point_bytes > 0 &&
            n > std::numeric_limits<std::uint32_t>::max() / header_.point_bytes) {
          throw InputError(file_, header_.data_line, "DATA",
                           fmt::format("POINTS {} of {} bytes each cannot be binary_compressed "
                                       "(more than 4 GiB unpacked)",
                                       n, header_.point_bytes));
        }
        check_compressed_sizes(read_compressed_sizes());
        return;
      case DataKind::kAscii:
        // A point takes several bytes of text, so more points than bytes is surely wrong; a claim
        // short of that is caught point by point, with the count that came.
        if (n > data.size()) {
          throw InputError(file_, header_.data_line, "DATA",
                           fmt::format("the ascii data ({} bytes) cannot hold POINTS {}: the file "
                                       "is truncated or POINTS is wrong",
                                       data.size(), n));
        }
        return;
    }
  }

  void read_binary() {
    const std::string_view data = bytes_.substr(header_.data_offset);
    for_used([&](std::size_t f, auto store) {
      const PcdField& field = header_.fields[f];
      decode_column(data.data() + field.offset, header_.point_bytes, header_.points, field, store);
    });
  }

  // The two uint32 before the LZF block: its compressed and its unpacked size [bytes].
  struct CompressedSizes {
    std::uint32_t compressed = 0, unpacked = 0;
  };

  CompressedSizes read_compressed_sizes() const {
    const std::string_view data = bytes_.substr(header_.data_offset);
    if (data.size() < 8) {
      throw InputError(
          file_, header_.data_line, "DATA",
          fmt::format("binary_compressed data of {} bytes lacks its 8-byte sizes", data.size()));
    }
    CompressedSizes sizes;
    std::memcpy(&sizes.compressed, data.data(), 4);
    std::memcpy(&sizes.unpacked, data.data() + 4, 4);
    return sizes;
  }

  // Every size the header and the block claim, against each other and against the file's bytes,
  // before anything is allocated for them: the points (24 bytes each in memory) and the unpacked
  // block then cost at most a fixed multiple of the file's size. Compared by division, so a huge
  // POINTS cannot wrap a product around.
  void check_compressed_sizes(const CompressedSizes& sizes) const {
    const std::size_t available = bytes_.size() - header_.data_offset - 8;
    const std::size_t n = header_.points;
    if (header_.point_bytes > 0 && n > sizes.unpacked / header_.point_bytes) {
      throw InputError(file_, header_.data_line, "DATA",
                       fmt::format("binary_compressed data unpacks to {} bytes; POINTS {} of {} "
                                   "bytes each need more",
                                   sizes.unpacked, n, header_.point_bytes));
    }
    if (n * header_.point_bytes != sizes.unpacked) {
      throw InputError(file_, header_.data_line, "DATA",
                       fmt::format("binary_compressed data unpacks to {} bytes; POINTS {} need {}",
                                   sizes.unpacked, n, n * header_.point_bytes));
    }
    if (available < sizes.compressed) {
      throw InputError(file_, header_.data_line, "DATA",
                       fmt::format("the data is truncated: {} bytes of LZF data, the header of "
                                   "the block says {}",
                                   available, sizes.compressed));
    }
    if (sizes.unpacked / kLzfMaxExpansion > sizes.compressed) {
      throw InputError(file_, header_.data_line, "DATA",
                       fmt::format("binary_compressed sizes are corrupt: {} bytes of LZF data "
                                   "cannot unpack to {} bytes (LZF expands at most {}-fold)",
                                   sizes.compressed, sizes.unpacked, kLzfMaxExpansion));
    }
  }

  void read_compressed() {
    const std::string_view data = bytes_.substr(header_.data_offset);
    const CompressedSizes sizes = read_compressed_sizes();  // checked by check_points_fit
    const std::size_t needed = sizes.unpacked;
    const std::uint32_t compressed_size = sizes.compressed;
    std::vector<char> fields(needed);
    if (needed > 0 && lzf_decompress(data.data() + 8, compressed_size, fields.data(),
                                     static_cast<unsigned>(needed)) != needed) {
      throw InputError(file_, header_.data_line, "DATA", "binary_compressed data is corrupt");
    }
    for_used([&](std::size_t f, auto store) {
      const PcdField& field = header_.fields[f];
      // All values of a field lie together, one after the other.
      decode_column(fields.data() + header_.points * field.offset, field.size, header_.points,
                    field, store);
    });
  }

  void read_ascii() {
    const std::string_view data = bytes_.substr(header_.data_offset);
    std::size_t pos = 0, line = header_.data_line, point = 0;
    std::vector<std::string_view> tokens;
    while (point < header_.points && pos < data.size()) {
      const std::size_t end = std::min(data.find('\n', pos), data.size());
      const std::string_view text = trim(data.substr(pos, end - pos));
      pos = end + 1;
      ++line;
      if (text.empty()) continue;
      tokens = split_fields(text);
      if (tokens.size() != header_.tokens) {
        throw InputError(
            file_, line, "",
            fmt::format("{} values, the header's fields need {}", tokens.size(), header_.tokens));
      }
      for_used([&](std::size_t f, auto store) {
        const PcdField& field = header_.fields[f];
        store(point,
              parse_double(tokens[field.column], {file_, line, field.name}, NonFinite::kAllow));
      });
      ++point;
    }
    if (point < header_.points) {
      throw InputError(
          file_, line, "",
          fmt::format("the ascii data ends after {} of {} points", point, header_.points));
    }
  }

  // Integer times are nanoseconds (Ouster's t), float times seconds; absolute stamps move into
  // time_base (pcd.hpp).
  void set_times() {
    const double time_scale = header_.fields[*used_.time].type == 'F' ? 1.0 : 1e-9;
    double smallest = std::numeric_limits<double>::infinity();
    bool absolute = false;
    for (const double time : time_) {
      if (!std::isfinite(time)) continue;
      smallest = std::min(smallest, time * time_scale);
      absolute = absolute || std::abs(time * time_scale) >= kAbsoluteTime;
    }
    if (absolute) cloud_.time_base = smallest;
    for (std::size_t i = 0; i < time_.size(); ++i) {
      cloud_.points[i].t = static_cast<float>(time_[i] * time_scale - cloud_.time_base);
    }
  }

  static constexpr double kAbsoluteTime = 1e4;  // [s] times at least this large are absolute
  // LZF's longest back reference packs 264 bytes into 3 (88-fold); 100 leaves a margin.
  static constexpr std::size_t kLzfMaxExpansion = 100;

  std::string_view bytes_;
  const PcdHeader& header_;
  const UsedFields& used_;
  const std::string& file_;
  PointCloud cloud_;
  std::vector<double> time_;
};

}  // namespace

std::string format_pcd(const PointCloud& cloud, PcdEncoding encoding) {
  const std::size_t n = cloud.points.size();
  switch (encoding) {
    case PcdEncoding::kAscii: {
      std::string bytes = pcd_header(n, "ascii");
      append_ascii(cloud, bytes);
      return bytes;
    }
    case PcdEncoding::kBinary: {
      std::string bytes = pcd_header(n, "binary");
      append_binary(cloud, bytes);
      return bytes;
    }
    case PcdEncoding::kBinaryCompressed: {
      std::string bytes = pcd_header(n, "binary_compressed");
      append_compressed(cloud, bytes);
      return bytes;
    }
  }
  throw std::invalid_argument("format_pcd: unknown encoding");
}

void write_pcd(const std::filesystem::path& path, const PointCloud& cloud, PcdEncoding encoding) {
  write_text_file(path, format_pcd(cloud, encoding));
}

PointCloud read_pcd(const std::filesystem::path& path) {
  return parse_pcd(read_text_file(path), path.string());
}

PointCloud parse_pcd(std::string_view bytes, const std::string& source_name) {
  const PcdHeader header = detail::parse_pcd_header(bytes, source_name);
  const UsedFields used = used_fields(header, source_name);
  return DataReader(bytes, header, used, source_name).read();
}

}  // namespace x2car::io
