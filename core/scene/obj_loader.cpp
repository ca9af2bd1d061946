#include "core/scene/obj_loader.h"

#include <array>
#include <charconv>
#include <cmath>
#include <limits>
#include <vector>

#include "core/spec/limits.h"
#include "core/util/error.h"

namespace loom {
namespace {

constexpr uint32_t kNone = std::numeric_limits<uint32_t>::max();

// A face corner: zero-based indices into the attribute lists (kNone: absent).
struct Corner {
  uint32_t position = kNone, texcoord = kNone, normal = kNone;
  bool operator==(const Corner&) const = default;
};

std::string_view Trim(std::string_view s) {
  const size_t first = s.find_first_not_of(" \t\r\f\v");
  if (first == std::string_view::npos) return {};
  return s.substr(first, s.find_last_not_of(" \t\r\f\v") - first + 1);
}

// Splits off the next blank-separated token of `rest`.
std::string_view NextToken(std::string_view& rest) {
  rest = Trim(rest);
  const size_t end = rest.find_first_of(" \t\r\f\v");
  const std::string_view token = rest.substr(0, end);
  rest = end == std::string_view::npos ? std::string_view() : rest.substr(end);
  return token;
}

// (position, uv, normal) triple → output vertex, open addressing with a mixing
// hash so that no choice of indices degrades it to a linear scan.
class VertexTable {
 public:
  // The index of `corner`'s vertex, or kNone with `*inserted` when it is new and
  // `next` (the next free output index) was recorded for it.
  uint32_t FindOrInsert(const Corner& corner, uint32_t next, bool* inserted) {
    if (2 * (size_ + 1) > slots_.size()) Grow();
    const size_t mask = slots_.size() - 1;
    for (size_t i = Hash(corner) & mask;; i = (i + 1) & mask) {
      Slot& slot = slots_[i];
      if (slot.vertex == kNone) {
        slot = {corner, next};
        ++size_;
        *inserted = true;
        return next;
      }
      if (slot.corner == corner) {
        *inserted = false;
        return slot.vertex;
      }
    }
  }

 private:
  struct Slot {
    Corner corner;
    uint32_t vertex = kNone;
  };

  static uint64_t Hash(const Corner& c) {
    uint64_t x = (uint64_t{c.position} << 32 | c.texcoord) ^ (uint64_t{c.normal} * 0x9e3779b97f4a7c15ULL);
    x ^= x >> 30;
    x *= 0xbf58476d1ce4e5b9ULL;
    x ^= x >> 27;
    x *= 0x94d049bb133111ebULL;
    return x ^ (x >> 31);
  }

  void Grow() {
    std::vector<Slot> old(std::max<size_t>(1024, 2 * slots_.size()));
    old.swap(slots_);
    size_ = 0;
    for (const Slot& slot : old) {
      bool inserted = false;
      if (slot.vertex != kNone) FindOrInsert(slot.corner, slot.vertex, &inserted);
    }
  }

  std::vector<Slot> slots_;
  size_t size_ = 0;
};

}  // namespace

MeshLimits::MeshLimits() : triangles(kMaxMeshTriangles), vertices(kMaxMeshVertices) {}

struct ObjParser::State {
  std::string source;
  MeshLimits limits;
  int64_t line = 0;        // number of the line being parsed, from 1
  std::string partial;     // a line not yet ended by the bytes fed so far
  std::vector<glm::vec3> positions, normals;
  std::vector<glm::vec2> texcoords;
  std::vector<Corner> face;
  VertexTable table;
  TriangleMesh mesh;
  int faces_seen = 0;
  bool corners_have_normals = false;
  bool finished = false;

  Error Invalid(const std::string& what) const {
    return Error(ErrorCode::kInvalidArgument, "mesh " + source + ": line " + std::to_string(line) + ": " + what);
  }
  Error Whole(const std::string& what) const {
    return Error(ErrorCode::kInvalidArgument, "mesh " + source + ": " + what);
  }

  float Number(std::string_view token, const char* statement) const {
    if (token.starts_with('+')) token.remove_prefix(1);  // from_chars takes no sign but '-'
    float value = 0.0f;
    const char* end = token.data() + token.size();
    const auto [ptr, ec] = std::from_chars(token.data(), end, value);
    if (ec == std::errc::result_out_of_range || (ec == std::errc() && ptr == end && !std::isfinite(value))) {
      throw Invalid("'" + std::string(token.substr(0, 32)) + "' in " + statement +
                    " is not a finite number (NaN or Inf)");
    }
    if (ec != std::errc() || ptr != end) {
      throw Invalid("'" + std::string(token.substr(0, 32)) + "' in " + statement + " is not a number");
    }
    return value;
  }

  // Reads `min`..`max` numbers of statement `name` into `out`; the rest stay 0.
  template <size_t N>
  std::array<float, N> Numbers(std::string_view rest, const char* name, size_t min, size_t max) const {
    std::array<float, N> out{};
    size_t count = 0;
    for (std::string_view token = NextToken(rest); !token.empty(); token = NextToken(rest), ++count) {
      if (count == max) throw Invalid(std::string(name) + " has more than " + std::to_string(max) + " numbers");
      const float value = Number(token, name);
      if (count < N) out[count] = value;
    }
    if (count < min) throw Invalid(std::string(name) + " needs at least " + std::to_string(min) + " numbers");
    return out;
  }

  template <typename T>
  void AddAttribute(std::vector<T>& list, T value, const char* what) {
    if (static_cast<int64_t>(list.size()) >= limits.vertices) {
      throw Invalid("more than " + std::to_string(limits.vertices) + " " + what);
    }
    list.push_back(value);
  }

  // One index of a face corner: 1-based, or negative counting back from the last
  // element defined so far. Returns the zero-based index.
  uint32_t Index(std::string_view token, size_t defined, const char* what) const {
    int64_t value = 0;
    const char* end = token.data() + token.size();
    const auto [ptr, ec] = std::from_chars(token.data(), end, value);
    if (ec != std::errc() || ptr != end) {
      throw Invalid("face index '" + std::string(token.substr(0, 32)) + "' is not an integer");
    }
    const int64_t count = static_cast<int64_t>(defined);
    if (value == 0) throw Invalid(std::string("face ") + what + " index 0 (OBJ counts from 1)");
    if (value > count || value < -count) {
      throw Invalid("face refers to " + std::string(what) + " " + std::string(token.substr(0, 32)) + ", but " +
                    std::to_string(count) + " " + what + (count == 1 ? " is" : "s are") + " defined before it");
    }
    return static_cast<uint32_t>(value > 0 ? value - 1 : count + value);
  }

  Corner ParseCorner(std::string_view token) const {
    Corner corner;
    const size_t slash = token.find('/');
    corner.position = Index(token.substr(0, slash), positions.size(), "position");
    if (slash == std::string_view::npos) return corner;
    const std::string_view rest = token.substr(slash + 1);
    const size_t second = rest.find('/');
    const std::string_view texcoord = rest.substr(0, second);
    if (!texcoord.empty()) corner.texcoord = Index(texcoord, texcoords.size(), "texture coordinate");
    if (second == std::string_view::npos) return corner;
    const std::string_view normal = rest.substr(second + 1);
    if (normal.empty() || normal.find('/') != std::string_view::npos) {
      throw Invalid("face corner '" + std::string(token.substr(0, 32)) + "' is not v, v/vt, v//vn or v/vt/vn");
    }
    corner.normal = Index(normal, this->normals.size(), "normal");
    return corner;
  }

  uint32_t Vertex(const Corner& corner) {
    bool inserted = false;
    const uint32_t next = static_cast<uint32_t>(mesh.positions.size());
    const uint32_t vertex = table.FindOrInsert(corner, next, &inserted);
    if (!inserted) return vertex;
    if (static_cast<int64_t>(next) >= limits.vertices) {
      throw Invalid("more than " + std::to_string(limits.vertices) + " distinct vertices");
    }
    mesh.positions.push_back(positions[corner.position]);
    if (corner.texcoord != kNone) mesh.uvs.push_back(texcoords[corner.texcoord]);
    if (corner.normal != kNone) mesh.normals.push_back(normals[corner.normal]);
    return vertex;
  }

  void Triangle(const Corner& a, const Corner& b, const Corner& c) {
    if (static_cast<int64_t>(mesh.triangle_count()) >= limits.triangles) {
      throw Invalid("more than " + std::to_string(limits.triangles) + " triangles");
    }
    for (const Corner* corner : {&a, &b, &c}) mesh.indices.push_back(Vertex(*corner));
  }

  void Face(std::string_view rest) {
    face.clear();
    for (std::string_view token = NextToken(rest); !token.empty(); token = NextToken(rest)) {
      const Corner corner = ParseCorner(token);
      if (faces_seen == 0 && face.empty()) corners_have_normals = corner.normal != kNone;
      if ((corner.normal != kNone) != corners_have_normals) {
        throw Invalid(corners_have_normals ? "a face corner without a normal, where the first face's have one"
                                           : "a face corner with a normal, where the first face's have none");
      }
      if (corner.texcoord == kNone && !texcoords.empty()) {
        throw Invalid("a face corner without a texture coordinate, though the file has them (vt)");
      }
      if (corner.texcoord != kNone && mesh.uvs.size() != mesh.positions.size()) {
        throw Invalid("a face corner with a texture coordinate, where earlier ones have none");
      }
      face.push_back(corner);
      // A fan emits its triangles as the corners come, so the caps bound a face too.
      if (face.size() == 5) {
        Triangle(face[0], face[1], face[2]);
        Triangle(face[0], face[2], face[3]);
      }
      if (face.size() >= 5) Triangle(face[0], face[face.size() - 2], face.back());
    }
    if (face.size() < 3) throw Invalid("a face needs at least 3 corners, this one has " + std::to_string(face.size()));
    if (face.size() == 3) Triangle(face[0], face[1], face[2]);
    if (face.size() == 4) {
      // Along the shorter diagonal: the flatter split of a non-planar quad.
      const float d02 = glm::length(positions[face[2].position] - positions[face[0].position]);
      const float d13 = glm::length(positions[face[3].position] - positions[face[1].position]);
      if (d02 < d13) {
        Triangle(face[0], face[1], face[2]);
        Triangle(face[0], face[2], face[3]);
      } else {
        Triangle(face[0], face[1], face[3]);
        Triangle(face[1], face[2], face[3]);
      }
    }
    ++faces_seen;
  }
};

ObjParser::ObjParser(std::string source, MeshLimits limits) : state_(std::make_unique<State>()) {
  state_->source = std::move(source);
  state_->limits = limits;
}

ObjParser::~ObjParser() = default;

void ObjParser::ParseLine(std::string_view line) {
  State& s = *state_;
  ++s.line;
  std::string_view rest = line.substr(0, line.find('#'));
  const std::string_view statement = NextToken(rest);
  if (statement == "v") {
    const auto xyz = s.Numbers<3>(rest, "v", 3, 7);
    s.AddAttribute(s.positions, glm::vec3(xyz[0], xyz[1], xyz[2]), "positions (v)");
  } else if (statement == "vt") {
    const auto uv = s.Numbers<2>(rest, "vt", 1, 3);
    s.AddAttribute(s.texcoords, glm::vec2(uv[0], uv[1]), "texture coordinates (vt)");
  } else if (statement == "vn") {
    const auto n = s.Numbers<3>(rest, "vn", 3, 3);
    s.AddAttribute(s.normals, glm::vec3(n[0], n[1], n[2]), "normals (vn)");
  } else if (statement == "f") {
    s.Face(rest);
  }
}

void ObjParser::Feed(std::string_view bytes) {
  State& s = *state_;
  if (s.finished) throw Error(ErrorCode::kInternal, "ObjParser::Feed after Finish");
  while (!bytes.empty()) {
    const size_t newline = bytes.find('\n');
    const std::string_view piece = bytes.substr(0, newline);
    if (s.partial.size() + piece.size() > kMaxObjLineBytes) {
      ++s.line;
      throw s.Invalid("longer than " + std::to_string(kMaxObjLineBytes) + " bytes");
    }
    if (newline == std::string_view::npos) {
      s.partial.append(piece);
      return;
    }
    if (s.partial.empty()) {
      ParseLine(piece);
    } else {
      s.partial.append(piece);
      ParseLine(s.partial);
      s.partial.clear();
    }
    bytes.remove_prefix(newline + 1);
  }
}

TriangleMesh ObjParser::Finish() {
  State& s = *state_;
  if (s.finished) throw Error(ErrorCode::kInternal, "ObjParser::Finish called twice");
  if (!s.partial.empty()) ParseLine(s.partial);
  s.finished = true;
  if (s.mesh.indices.empty()) throw s.Whole("has no faces");
  return std::move(s.mesh);
}

TriangleMesh ParseObj(std::string_view text, const std::string& source, MeshLimits limits) {
  ObjParser parser(source, limits);
  parser.Feed(text);
  return parser.Finish();
}

}  // namespace loom
