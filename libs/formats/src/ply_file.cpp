#include "dlo/formats/ply_file.h"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstdlib>
#include <cstring>
#include <fstream>
#include <limits>
#include <sstream>
#include <vector>

#include "dlo/files/error.h"

namespace dlo {

namespace {

enum class Encoding { kAscii, kLittleEndian, kBigEndian };

/// Vertices reserved up front, at most (12 MB); larger clouds grow as they are read.
constexpr size_t kMaxReservedVertices = size_t{1} << 20;

struct Property {
  std::string name;
  std::string type;             ///< scalar type, or the item type of a list
  std::string list_count_type;  ///< empty for scalars
};

struct Element {
  std::string name;
  size_t count = 0;
  std::vector<Property> properties;
};

/// Size in bytes of a PLY scalar type, 0 if unknown.
size_t typeSize(const std::string& t) {
  if (t == "char" || t == "uchar" || t == "int8" || t == "uint8") return 1;
  if (t == "short" || t == "ushort" || t == "int16" || t == "uint16") return 2;
  if (t == "int" || t == "uint" || t == "float" || t == "int32" || t == "uint32" || t == "float32")
    return 4;
  if (t == "double" || t == "float64") return 8;
  return 0;
}

/// Whether `v` is finite and within float's range: a double or double-typed property beyond it
/// would not convert to a finite float (the conversion is even undefined behaviour).
bool fitsFloat(double v) {
  return std::abs(v) <= static_cast<double>(std::numeric_limits<float>::max());
}

bool hostIsLittleEndian() {
  const std::uint16_t one = 1;
  std::uint8_t first;
  std::memcpy(&first, &one, 1);
  return first == 1;
}

/// Reads a PLY file sequentially from a stream; every failure becomes one InputError naming the
/// file.
class PlyReader {
 public:
  PlyReader(std::istream& in, const std::string& path) : path_(path), in_(in) {}

  PointCloud read() {
    readHeader();
    PointCloud points;
    for (const Element& e : elements_) {
      if (e.name == "vertex") {
        readVertices(e, points);
        return points;
      }
      // Items without properties occupy no bytes: nothing to skip, however many are declared.
      if (e.properties.empty()) continue;
      for (size_t i = 0; i < e.count; ++i) skipItem(e, i);
    }
    fail("it has no vertex element");
    return points;
  }

 private:
  [[noreturn]] void fail(const std::string& why) const {
    throw InputError("cannot read PLY file '" + path_ + "': " + why + ".");
  }

  void readHeader() {
    std::string line;
    if (!std::getline(in_, line) || trimmed(line) != "ply") fail("it does not start with 'ply'");
    bool have_format = false;
    // A header is a few dozen lines; the limit stops a binary file without "end_header" early.
    for (int n = 0; n < 10000; ++n) {
      if (!std::getline(in_, line)) fail("the header has no end_header line");
      std::istringstream words(trimmed(line));
      std::string word;
      words >> word;
      if (word == "end_header") {
        if (!have_format) fail("the header has no format line");
        return;
      }
      if (word == "format") {
        std::string format;
        words >> format;
        if (format == "ascii")
          encoding_ = Encoding::kAscii;
        else if (format == "binary_little_endian")
          encoding_ = Encoding::kLittleEndian;
        else if (format == "binary_big_endian")
          encoding_ = Encoding::kBigEndian;
        else
          fail("unknown format '" + format + "'");
        have_format = true;
      } else if (word == "element") {
        Element e;
        long long count = -1;
        if (!(words >> e.name >> count) || count < 0) fail("bad element line '" + line + "'");
        e.count = static_cast<size_t>(count);
        elements_.push_back(e);
      } else if (word == "property") {
        if (elements_.empty()) fail("a property comes before any element");
        Property p;
        words >> p.type;
        if (p.type == "list") words >> p.list_count_type >> p.type;
        words >> p.name;
        if (p.name.empty() || typeSize(p.type) == 0 ||
            (!p.list_count_type.empty() && typeSize(p.list_count_type) == 0)) {
          fail("bad property line '" + trimmed(line) + "'");
        }
        elements_.back().properties.push_back(p);
      }
      // comment, obj_info and unknown keywords carry nothing we need.
    }
    fail("the header has no end_header line");
  }

  static std::string trimmed(const std::string& s) {
    const auto b = s.find_first_not_of(" \t\r");
    if (b == std::string::npos) return {};
    return s.substr(b, s.find_last_not_of(" \t\r") - b + 1);
  }

  /// One scalar as double, binary encodings.
  double readBinary(const std::string& type, size_t item, const Element& e) {
    unsigned char bytes[8];
    const size_t n = typeSize(type);
    if (!in_.read(reinterpret_cast<char*>(bytes), static_cast<std::streamsize>(n)))
      truncated(item, e);
    if ((encoding_ == Encoding::kLittleEndian) != hostIsLittleEndian())
      std::reverse(bytes, bytes + n);
    auto as = [&](auto v) {
      std::memcpy(&v, bytes, sizeof(v));
      return static_cast<double>(v);
    };
    if (type == "char" || type == "int8") return as(std::int8_t());
    if (type == "uchar" || type == "uint8") return as(std::uint8_t());
    if (type == "short" || type == "int16") return as(std::int16_t());
    if (type == "ushort" || type == "uint16") return as(std::uint16_t());
    if (type == "int" || type == "int32") return as(std::int32_t());
    if (type == "uint" || type == "uint32") return as(std::uint32_t());
    if (type == "float" || type == "float32") return as(float());
    return as(double());
  }

  double readAscii(size_t item, const Element& e) {
    // Through strtod, which unlike operator>> accepts the "nan" and "inf" some exporters write.
    std::string token;
    if (!(in_ >> token)) truncated(item, e);
    char* end = nullptr;
    const double v = std::strtod(token.c_str(), &end);
    if (end == token.c_str() || *end != '\0') truncated(item, e);
    return v;
  }

  double readScalar(const std::string& type, size_t item, const Element& e) {
    return encoding_ == Encoding::kAscii ? readAscii(item, e) : readBinary(type, item, e);
  }

  [[noreturn]] void truncated(size_t item, const Element& e) const {
    fail("it ends or is malformed after " + std::to_string(item) + " of its " +
         std::to_string(e.count) + " " + e.name + " items");
  }

  /// Reads one item of `e`, returning its scalar properties in order (lists are skipped).
  void readItem(const Element& e, size_t item, std::vector<double>& scalars) {
    scalars.clear();
    for (const Property& p : e.properties) {
      if (p.list_count_type.empty()) {
        scalars.push_back(readScalar(p.type, item, e));
        continue;
      }
      const double n = readScalar(p.list_count_type, item, e);
      if (!(n >= 0 && n < 1e6)) truncated(item, e);
      for (int k = 0; k < static_cast<int>(n); ++k) readScalar(p.type, item, e);
    }
  }

  void skipItem(const Element& e, size_t item) {
    std::vector<double> scalars;
    readItem(e, item, scalars);
  }

  void readVertices(const Element& e, PointCloud& points) {
    int ix = -1, iy = -1, iz = -1, scalar = 0;
    for (const Property& p : e.properties) {
      if (!p.list_count_type.empty()) continue;
      if (p.name == "x") ix = scalar;
      if (p.name == "y") iy = scalar;
      if (p.name == "z") iz = scalar;
      ++scalar;
    }
    if (ix < 0 || iy < 0 || iz < 0) fail("its vertices have no x, y and z properties");
    // The header's count is not trusted with memory before the vertices are actually read.
    points.reserve(std::min<size_t>(e.count, kMaxReservedVertices));
    std::vector<double> v;
    for (size_t i = 0; i < e.count; ++i) {
      readItem(e, i, v);
      if (fitsFloat(v[ix]) && fitsFloat(v[iy]) && fitsFloat(v[iz]))
        points.emplace_back(static_cast<float>(v[ix]), static_cast<float>(v[iy]),
                            static_cast<float>(v[iz]));
    }
  }

  std::string path_;
  std::istream& in_;
  Encoding encoding_ = Encoding::kAscii;
  std::vector<Element> elements_;
};

}  // namespace

PointCloud loadPlyStream(std::istream& in, const std::string& name) {
  return PlyReader(in, name).read();
}

PointCloud loadPlyFile(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  if (!in) throw InputError("cannot read PLY file '" + path + "': no such file or not readable.");
  return loadPlyStream(in, path);
}

}  // namespace dlo
