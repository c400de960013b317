#include "common/mesh/mesh.h"

#include "common/mesh/assimp_mesh.h"

#include <cctype>
#include <sstream>

#include <cctype>
#include <charconv>
#include <cmath>
#include <cstring>
#include <limits>
#include <string>
#include <string_view>

#include <Eigen/Geometry>

#include "common/util/error.h"
#include "common/util/file.h"

namespace uw {
namespace {

static_assert(__BYTE_ORDER__ == __ORDER_LITTLE_ENDIAN__,
              "PLY binary_little_endian is read and written by memcpy");

// A PLY property: a scalar, or a list with a count type and an item type.
struct Property {
  enum class Type {
    kInt8,
    kUint8,
    kInt16,
    kUint16,
    kInt32,
    kUint32,
    kFloat32,
    kFloat64
  };
  std::string name;
  Type type = Type::kFloat32;
  bool is_list = false;
  Type count_type = Type::kUint8;
};

struct Element {
  std::string name;
  size_t count = 0;
  std::vector<Property> properties;
  int header_line = 0;
};

struct Header {
  bool binary = false;
  std::vector<Element> elements;
  size_t data_offset = 0;  // first byte after "end_header\n"
};

// The record being read, for error messages: "line 12 (face 3)" in ASCII,
// "face 3" in binary files. Formatted only when an error is thrown.
struct Where {
  const Element* element;
  size_t record;
  int line;  // 0 in binary files
};

std::ostream& operator<<(std::ostream& stream, const Where& where) {
  if (where.line > 0) {
    return stream << "line " << where.line << " (" << where.element->name << " "
                  << where.record << ")";
  }
  return stream << where.element->name << " " << where.record;
}

size_t TypeSize(Property::Type type) {
  switch (type) {
    case Property::Type::kInt8:
    case Property::Type::kUint8:
      return 1;
    case Property::Type::kInt16:
    case Property::Type::kUint16:
      return 2;
    case Property::Type::kInt32:
    case Property::Type::kUint32:
    case Property::Type::kFloat32:
      return 4;
    case Property::Type::kFloat64:
      return 8;
  }
  return 0;
}

bool IsInteger(Property::Type type) {
  return type != Property::Type::kFloat32 && type != Property::Type::kFloat64;
}

// Both the PLY 1.0 names and the sized aliases most writers use.
bool ParseType(std::string_view name, Property::Type* type) {
  using Type = Property::Type;
  static const std::pair<std::string_view, Type> kNames[] = {
      {"char", Type::kInt8},      {"int8", Type::kInt8},
      {"uchar", Type::kUint8},    {"uint8", Type::kUint8},
      {"short", Type::kInt16},    {"int16", Type::kInt16},
      {"ushort", Type::kUint16},  {"uint16", Type::kUint16},
      {"int", Type::kInt32},      {"int32", Type::kInt32},
      {"uint", Type::kUint32},    {"uint32", Type::kUint32},
      {"float", Type::kFloat32},  {"float32", Type::kFloat32},
      {"double", Type::kFloat64}, {"float64", Type::kFloat64}};
  for (const auto& [candidate, candidate_type] : kNames) {
    if (name == candidate) {
      *type = candidate_type;
      return true;
    }
  }
  return false;
}

std::vector<std::string_view> SplitWhitespace(std::string_view line) {
  std::vector<std::string_view> tokens;
  size_t pos = 0;
  while (pos < line.size()) {
    while (pos < line.size() &&
           std::isspace(static_cast<unsigned char>(line[pos]))) {
      ++pos;
    }
    const size_t start = pos;
    while (pos < line.size() &&
           !std::isspace(static_cast<unsigned char>(line[pos]))) {
      ++pos;
    }
    if (pos > start) tokens.push_back(line.substr(start, pos - start));
  }
  return tokens;
}

// Reads lines one at a time from the file's bytes, tracking line numbers.
class LineReader {
 public:
  explicit LineReader(const std::string& data) : data_(data) {}
  bool Next(std::string_view* line) {
    if (pos_ >= data_.size()) return false;
    size_t end = data_.find('\n', pos_);
    const size_t next = end == std::string::npos ? data_.size() : end + 1;
    if (end == std::string::npos) end = data_.size();
    std::string_view text(data_.data() + pos_, end - pos_);
    if (!text.empty() && text.back() == '\r') text.remove_suffix(1);
    *line = text;
    pos_ = next;
    ++line_number_;
    return true;
  }
  int line_number() const { return line_number_; }
  size_t pos() const { return pos_; }

 private:
  const std::string& data_;
  size_t pos_ = 0;
  int line_number_ = 0;
};

Header ParseHeader(const std::string& data, const std::string& source) {
  LineReader reader(data);
  std::string_view line;
  const auto fail = [&](const std::string& what) {
    return ErrorAt(source, ":", reader.line_number(), ": ", what);
  };
  if (!reader.Next(&line) || line != "ply") {
    throw ErrorAt(source, ":1: not a PLY file (first line must be \"ply\")");
  }
  Header header;
  bool have_format = false;
  while (true) {
    if (!reader.Next(&line)) throw fail("file ends inside the header");
    const std::vector<std::string_view> tokens = SplitWhitespace(line);
    if (tokens.empty()) continue;
    const std::string_view keyword = tokens[0];
    if (keyword == "comment" || keyword == "obj_info") continue;
    if (keyword == "end_header") break;
    if (keyword == "format") {
      if (tokens.size() != 3 || tokens[2] != "1.0") {
        throw fail("expected \"format <ascii|binary_little_endian> 1.0\"");
      }
      if (tokens[1] == "ascii") {
        header.binary = false;
      } else if (tokens[1] == "binary_little_endian") {
        header.binary = true;
      } else {
        throw fail("unsupported format \"" + std::string(tokens[1]) +
                   "\" (ascii or binary_little_endian)");
      }
      have_format = true;
    } else if (keyword == "element") {
      size_t count = 0;
      if (tokens.size() != 3 ||
          std::from_chars(tokens[2].data(), tokens[2].data() + tokens[2].size(),
                          count)
                  .ptr != tokens[2].data() + tokens[2].size()) {
        throw fail("expected \"element <name> <count>\"");
      }
      header.elements.push_back(
          {std::string(tokens[1]), count, {}, reader.line_number()});
    } else if (keyword == "property") {
      if (header.elements.empty()) throw fail("property before any element");
      Property property;
      if (tokens.size() == 5 && tokens[1] == "list") {
        property.is_list = true;
        if (!ParseType(tokens[2], &property.count_type) ||
            !ParseType(tokens[3], &property.type) ||
            !IsInteger(property.count_type)) {
          throw fail("bad list property types \"" + std::string(tokens[2]) +
                     " " + std::string(tokens[3]) + "\"");
        }
        property.name = tokens[4];
      } else if (tokens.size() == 3) {
        if (!ParseType(tokens[1], &property.type)) {
          throw fail("unknown property type \"" + std::string(tokens[1]) +
                     "\"");
        }
        property.name = tokens[2];
      } else {
        throw fail(
            "expected \"property <type> <name>\" or \"property list "
            "<count type> <item type> <name>\"");
      }
      header.elements.back().properties.push_back(property);
    } else {
      throw fail("unknown header keyword \"" + std::string(keyword) + "\"");
    }
  }
  if (!have_format) throw fail("header has no format line");
  header.data_offset = reader.pos();
  return header;
}

// Where the reader needs vertex coordinates and face indices.
struct Layout {
  const Element* vertex = nullptr;
  const Element* face = nullptr;
  int xyz[3] = {-1, -1, -1};  // property indices of x, y, z in the vertex
  int indices = -1;           // property index of the face's index list
};

Layout FindLayout(const Header& header, const std::string& source) {
  Layout layout;
  for (const Element& element : header.elements) {
    if (element.name == "vertex") layout.vertex = &element;
    if (element.name == "face") layout.face = &element;
  }
  if (layout.vertex == nullptr) {
    throw ErrorAt(source, ": header has no \"vertex\" element");
  }
  if (layout.vertex->count >
      static_cast<size_t>(std::numeric_limits<int>::max())) {
    throw ErrorAt(source, ":", layout.vertex->header_line, ": ",
                  layout.vertex->count,
                  " vertices exceed what int indices can address");
  }
  const char* kAxes[3] = {"x", "y", "z"};
  for (size_t i = 0; i < layout.vertex->properties.size(); ++i) {
    const Property& property = layout.vertex->properties[i];
    for (int axis = 0; axis < 3; ++axis) {
      if (property.name != kAxes[axis]) continue;
      if (property.is_list || IsInteger(property.type)) {
        throw ErrorAt(source, ":", layout.vertex->header_line,
                      ": vertex property ", kAxes[axis],
                      " must be float or double");
      }
      layout.xyz[axis] = static_cast<int>(i);
    }
  }
  for (int axis = 0; axis < 3; ++axis) {
    if (layout.xyz[axis] < 0) {
      throw ErrorAt(source, ":", layout.vertex->header_line,
                    ": vertex element has no property ", kAxes[axis]);
    }
  }
  if (layout.face != nullptr) {
    for (size_t i = 0; i < layout.face->properties.size(); ++i) {
      const Property& property = layout.face->properties[i];
      if (property.name == "vertex_indices" ||
          property.name == "vertex_index") {
        if (!property.is_list || !IsInteger(property.type)) {
          throw ErrorAt(source, ":", layout.face->header_line, ": face ",
                        property.name, " must be a list of integers");
        }
        layout.indices = static_cast<int>(i);
      }
    }
    if (layout.indices < 0) {
      throw ErrorAt(source, ":", layout.face->header_line,
                    ": face element has no vertex_indices list");
    }
  }
  return layout;
}

// Collects vertices and faces as elements are read, whatever the encoding,
// and validates them.
class MeshBuilder {
 public:
  MeshBuilder(const Layout& layout, const std::string& source,
              bool drop_non_finite)
      : layout_(layout), source_(source), drop_non_finite_(drop_non_finite) {}

  void AddVertex(const double (&xyz)[3], const Where& where) {
    for (const double coordinate : xyz) {
      if (!std::isfinite(coordinate)) {
        if (!drop_non_finite_) {
          throw ErrorAt(source_, ": ", where, ": non-finite vertex coordinate");
        }
        ++num_non_finite_;
        break;
      }
    }
    mesh_.vertices.emplace_back(xyz[0], xyz[1], xyz[2]);
  }

  void AddFace(const std::vector<int64_t>& indices, const Where& where) {
    const int64_t num_vertices = static_cast<int64_t>(layout_.vertex->count);
    for (const int64_t index : indices) {
      if (index < 0 || index >= num_vertices) {
        throw ErrorAt(source_, ": ", where, ": vertex index ", index,
                      " out of range (", num_vertices, " vertices)");
      }
    }
    const auto at = [&indices](size_t i) {
      return static_cast<int>(indices[i]);
    };
    if (indices.size() == 3) {
      mesh_.triangles.emplace_back(at(0), at(1), at(2));
    } else if (indices.size() == 4) {
      // A quad splits along its 0-2 diagonal, keeping the winding.
      mesh_.triangles.emplace_back(at(0), at(1), at(2));
      mesh_.triangles.emplace_back(at(0), at(2), at(3));
    } else {
      throw ErrorAt(source_, ": ", where, ": face with ", indices.size(),
                    " vertices (only triangles and quads are read)");
    }
  }

  // The mesh, without its non-finite vertices and the faces that use them
  // (counted in *num_dropped when given).
  TriangleMesh Take(size_t* num_dropped) {
    if (num_dropped != nullptr) *num_dropped = num_non_finite_;
    if (num_non_finite_ == 0) return std::move(mesh_);
    TriangleMesh kept;
    std::vector<int> new_index(mesh_.vertices.size(), -1);
    for (size_t v = 0; v < mesh_.vertices.size(); ++v) {
      if (!mesh_.vertices[v].allFinite()) continue;
      new_index[v] = static_cast<int>(kept.vertices.size());
      kept.vertices.push_back(mesh_.vertices[v]);
    }
    for (const Eigen::Vector3i& triangle : mesh_.triangles) {
      const Eigen::Vector3i renumbered(new_index[triangle(0)],
                                       new_index[triangle(1)],
                                       new_index[triangle(2)]);
      if (renumbered.minCoeff() >= 0) kept.triangles.push_back(renumbered);
    }
    return kept;
  }

 private:
  const Layout& layout_;
  const std::string& source_;
  const bool drop_non_finite_;
  size_t num_non_finite_ = 0;
  TriangleMesh mesh_;
};

template <typename T>
bool ParseNumber(std::string_view token, T* value) {
  const char* end = token.data() + token.size();
  return std::from_chars(token.data(), end, *value).ptr == end;
}

TriangleMesh ReadAscii(const std::string& data, const Header& header,
                       const Layout& layout, const std::string& source,
                       size_t* num_dropped) {
  MeshBuilder builder(layout, source, num_dropped != nullptr);
  LineReader reader(data);
  std::string_view line;
  while (reader.pos() < header.data_offset) reader.Next(&line);
  std::vector<int64_t> indices;
  for (const Element& element : header.elements) {
    const bool is_vertex = &element == layout.vertex;
    const bool is_face = &element == layout.face;
    for (size_t record = 0; record < element.count; ++record) {
      do {
        if (!reader.Next(&line)) {
          throw ErrorAt(source, ": file ends before ", element.name, " ",
                        record, " (header announces ", element.count, ")");
        }
      } while (SplitWhitespace(line).empty());
      const Where where{&element, record, reader.line_number()};
      const std::vector<std::string_view> tokens = SplitWhitespace(line);
      size_t next = 0;
      const auto token = [&]() {
        if (next >= tokens.size()) {
          throw ErrorAt(source, ": ", where, ": too few values");
        }
        return tokens[next++];
      };
      double xyz[3] = {0.0, 0.0, 0.0};
      for (size_t p = 0; p < element.properties.size(); ++p) {
        const Property& property = element.properties[p];
        if (property.is_list) {
          const std::string_view count_token = token();
          size_t count = 0;
          if (!ParseNumber(count_token, &count)) {
            throw ErrorAt(source, ": ", where, ": bad list count \"",
                          count_token, "\"");
          }
          if (is_face && static_cast<int>(p) == layout.indices) {
            indices.clear();
            for (size_t i = 0; i < count; ++i) {
              const std::string_view index_token = token();
              int64_t index = 0;
              if (!ParseNumber(index_token, &index)) {
                throw ErrorAt(source, ": ", where, ": bad vertex index \"",
                              index_token, "\"");
              }
              indices.push_back(index);
            }
          } else {
            for (size_t i = 0; i < count; ++i) token();
          }
          continue;
        }
        const std::string_view value_token = token();
        double value = 0.0;
        if (!ParseNumber(value_token, &value)) {
          throw ErrorAt(source, ": ", where, ": bad number \"", value_token,
                        "\" for property ", property.name);
        }
        if (is_vertex) {
          for (int axis = 0; axis < 3; ++axis) {
            if (static_cast<int>(p) == layout.xyz[axis]) xyz[axis] = value;
          }
        }
      }
      if (next != tokens.size()) {
        throw ErrorAt(source, ": ", where, ": ", tokens.size() - next,
                      " values more than the header declares");
      }
      if (is_vertex) builder.AddVertex(xyz, where);
      if (is_face) builder.AddFace(indices, where);
    }
  }
  while (reader.Next(&line)) {
    if (!SplitWhitespace(line).empty()) {
      throw ErrorAt(source, ": line ", reader.line_number(),
                    ": data after the last element");
    }
  }
  return builder.Take(num_dropped);
}

// Sequential reader over the binary body; errors name the byte offset.
class BinaryReader {
 public:
  BinaryReader(const std::string& data, size_t pos, const std::string& source)
      : data_(data), pos_(pos), source_(source) {}

  double Scalar(Property::Type type, const Where& where) {
    const size_t size = TypeSize(type);
    if (data_.size() - pos_ < size) {
      throw ErrorAt(source_, ": byte ", pos_, ": file ends inside ", where);
    }
    const char* bytes = data_.data() + pos_;
    pos_ += size;
    switch (type) {
      case Property::Type::kInt8:
        return Load<int8_t>(bytes);
      case Property::Type::kUint8:
        return Load<uint8_t>(bytes);
      case Property::Type::kInt16:
        return Load<int16_t>(bytes);
      case Property::Type::kUint16:
        return Load<uint16_t>(bytes);
      case Property::Type::kInt32:
        return Load<int32_t>(bytes);
      case Property::Type::kUint32:
        return Load<uint32_t>(bytes);
      case Property::Type::kFloat32:
        return Load<float>(bytes);
      case Property::Type::kFloat64:
        return Load<double>(bytes);
    }
    return 0.0;
  }

  void Skip(size_t bytes, const Where& where) {
    if (data_.size() - pos_ < bytes) {
      throw ErrorAt(source_, ": byte ", pos_, ": file ends inside ", where);
    }
    pos_ += bytes;
  }

  size_t pos() const { return pos_; }
  size_t remaining() const { return data_.size() - pos_; }

 private:
  template <typename T>
  static T Load(const char* bytes) {
    T value;
    std::memcpy(&value, bytes, sizeof(T));
    return value;
  }

  const std::string& data_;
  size_t pos_;
  const std::string& source_;
};

TriangleMesh ReadBinary(const std::string& data, const Header& header,
                        const Layout& layout, const std::string& source,
                        size_t* num_dropped) {
  MeshBuilder builder(layout, source, num_dropped != nullptr);
  BinaryReader reader(data, header.data_offset, source);
  std::vector<int64_t> indices;
  for (const Element& element : header.elements) {
    // Every record takes at least this many bytes; a count that cannot fit
    // in the rest of the file is corrupt, and must not size an allocation.
    size_t min_record_bytes = 0;
    for (const Property& property : element.properties) {
      min_record_bytes +=
          TypeSize(property.is_list ? property.count_type : property.type);
    }
    if (min_record_bytes > 0 &&
        element.count > reader.remaining() / min_record_bytes) {
      throw ErrorAt(source, ":", element.header_line, ": ", element.count, " ",
                    element.name, " records cannot fit in the ",
                    reader.remaining(), " bytes that follow the header");
    }
    const bool is_vertex = &element == layout.vertex;
    const bool is_face = &element == layout.face;
    for (size_t record = 0; record < element.count; ++record) {
      const Where where{&element, record, 0};
      double xyz[3] = {0.0, 0.0, 0.0};
      for (size_t p = 0; p < element.properties.size(); ++p) {
        const Property& property = element.properties[p];
        if (property.is_list) {
          const double count = reader.Scalar(property.count_type, where);
          if (count < 0) {
            throw ErrorAt(source, ": ", where, ": negative list count");
          }
          const size_t n = static_cast<size_t>(count);
          if (is_face && static_cast<int>(p) == layout.indices) {
            indices.clear();
            for (size_t i = 0; i < n; ++i) {
              indices.push_back(
                  static_cast<int64_t>(reader.Scalar(property.type, where)));
            }
          } else {
            reader.Skip(n * TypeSize(property.type), where);
          }
          continue;
        }
        if (is_vertex) {
          const double value = reader.Scalar(property.type, where);
          for (int axis = 0; axis < 3; ++axis) {
            if (static_cast<int>(p) == layout.xyz[axis]) xyz[axis] = value;
          }
        } else {
          reader.Skip(TypeSize(property.type), where);
        }
      }
      if (is_vertex) builder.AddVertex(xyz, where);
      if (is_face) builder.AddFace(indices, where);
    }
  }
  if (reader.remaining() != 0) {
    throw ErrorAt(source, ": byte ", reader.pos(), ": ", reader.remaining(),
                  " bytes after the last element");
  }
  return builder.Take(num_dropped);
}

template <typename T>
void Append(std::string* buffer, const T& value) {
  buffer->append(reinterpret_cast<const char*>(&value), sizeof(T));
}

}  // namespace

Eigen::Vector3d TriangleMesh::TriangleNormal(size_t triangle) const {
  const Eigen::Vector3i& t = triangles[triangle];
  const Eigen::Vector3d& a = vertices[t[0]];
  return (vertices[t[1]] - a).cross(vertices[t[2]] - a).normalized();
}

void WritePly(const TriangleMesh& mesh, const std::filesystem::path& path,
              const std::string& frame) {
  if (frame.empty() || frame.find_first_of("\r\n") != std::string::npos) {
    throw ErrorAt(path.string(),
                  ": the mesh's frame must be stated on one line, got '", frame,
                  "'");
  }
  // Refuse what ReadPly would reject, so that every written mesh reads back.
  const int64_t num_vertices = static_cast<int64_t>(mesh.vertices.size());
  if (num_vertices > std::numeric_limits<int>::max()) {
    throw ErrorAt(path.string(), ": ", num_vertices,
                  " vertices exceed what int indices can address");
  }
  for (size_t i = 0; i < mesh.vertices.size(); ++i) {
    if (!mesh.vertices[i].allFinite()) {
      throw ErrorAt(path.string(), ": vertex ", i,
                    " has a non-finite coordinate");
    }
  }
  for (size_t i = 0; i < mesh.triangles.size(); ++i) {
    for (int k = 0; k < 3; ++k) {
      const int index = mesh.triangles[i][k];
      if (index < 0 || index >= num_vertices) {
        throw ErrorAt(path.string(), ": triangle ", i, ": vertex index ", index,
                      " out of range (", num_vertices, " vertices)");
      }
    }
  }
  WriteFilesAtomically(
      {{path,
        [&mesh, &frame](std::ostream& stream) {
          stream << "ply\n"
                    "format binary_little_endian 1.0\n"
                    "comment "
                 << frame
                 << "\n"
                    "element vertex "
                 << mesh.vertices.size()
                 << "\n"
                    "property double x\n"
                    "property double y\n"
                    "property double z\n"
                    "element face "
                 << mesh.triangles.size()
                 << "\n"
                    "property list uchar int vertex_indices\n"
                    "end_header\n";
          // Buffered in blocks: one stream write per value is several
          // times slower for meshes of millions of triangles.
          constexpr size_t kBlockBytes = 1 << 20;
          std::string block;
          block.reserve(kBlockBytes + 64);
          const auto flush = [&](bool force) {
            if (force || block.size() >= kBlockBytes) {
              stream.write(block.data(),
                           static_cast<std::streamsize>(block.size()));
              block.clear();
            }
          };
          for (const Eigen::Vector3d& vertex : mesh.vertices) {
            for (int k = 0; k < 3; ++k) Append(&block, vertex[k]);
            flush(false);
          }
          for (const Eigen::Vector3i& triangle : mesh.triangles) {
            Append(&block, uint8_t{3});
            for (int k = 0; k < 3; ++k) Append(&block, int32_t{triangle[k]});
            flush(false);
          }
          flush(true);
        }}},
      /*binary=*/true);
}

namespace {

// num_dropped: null refuses non-finite vertices, otherwise drops them.
TriangleMesh ReadPlyFile(const std::filesystem::path& path,
                         size_t* num_dropped) {
  const std::string source = path.string();
  const std::string data = ReadFileToString(path);
  const Header header = ParseHeader(data, source);
  const Layout layout = FindLayout(header, source);
  return header.binary ? ReadBinary(data, header, layout, source, num_dropped)
                       : ReadAscii(data, header, layout, source, num_dropped);
}

}  // namespace

TriangleMesh ReadPly(const std::filesystem::path& path) {
  return ReadPlyFile(path, nullptr);
}

TriangleMesh ReadPlyDroppingNonFinite(const std::filesystem::path& path,
                                      size_t* num_dropped) {
  size_t dropped = 0;
  TriangleMesh mesh = ReadPlyFile(path, &dropped);
  if (num_dropped != nullptr) *num_dropped = dropped;
  return mesh;
}

TriangleMesh ReadObj(const std::filesystem::path& path) {
  const std::string source = path.string();
  std::istringstream in(ReadFileToString(path));
  TriangleMesh mesh;
  std::string line;
  for (int number = 1; std::getline(in, line); ++number) {
    std::istringstream fields(line);
    std::string keyword;
    if (!(fields >> keyword) || keyword[0] == '#') continue;
    if (keyword == "v") {
      Eigen::Vector3d vertex;
      if (!(fields >> vertex.x() >> vertex.y() >> vertex.z()) ||
          !vertex.allFinite()) {
        throw ErrorAt(source, ":", number, ": a vertex needs 3 finite numbers");
      }
      mesh.vertices.push_back(vertex);
    } else if (keyword == "f") {
      std::vector<int> corners;
      std::string corner;
      while (fields >> corner) {
        int index = 0;
        try {
          size_t used = 0;
          index = std::stoi(corner, &used);
          if (used < corner.size() && corner[used] != '/') throw 0;
        } catch (...) {
          throw ErrorAt(source, ":", number, ": bad face index '", corner, "'");
        }
        const int count = static_cast<int>(mesh.vertices.size());
        const int resolved = index > 0 ? index - 1 : count + index;
        if (index == 0 || resolved < 0 || resolved >= count) {
          throw ErrorAt(source, ":", number, ": face index ", index,
                        " out of range (", count, " vertices so far)");
        }
        corners.push_back(resolved);
      }
      if (corners.size() < 3) {
        throw ErrorAt(source, ":", number, ": a face needs >= 3 vertices");
      }
      for (size_t k = 1; k + 1 < corners.size(); ++k) {
        mesh.triangles.emplace_back(corners[0], corners[k], corners[k + 1]);
      }
    }
  }
  if (mesh.triangles.empty()) throw ErrorAt(source, ": no faces");
  return mesh;
}

TriangleMesh ReadMesh(const std::filesystem::path& path) {
  std::string extension = path.extension().string();
  for (char& c : extension) c = static_cast<char>(std::tolower(c));
  if (extension == ".ply") return ReadPly(path);
  if (extension == ".obj") return ReadObj(path);
  return ReadAssimpMesh(path);
}

}  // namespace uw
