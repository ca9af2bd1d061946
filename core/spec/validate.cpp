#include "core/spec/validate.h"

#include <google/protobuf/descriptor.h>
#include <google/protobuf/message.h>

#include <algorithm>
#include <array>
#include <cctype>
#include <cmath>
#include <cstdio>
#include <limits>
#include <type_traits>
#include <utility>

#include "core/spec/defaults.h"
#include "core/spec/limits.h"
#include "core/util/error.h"

namespace loom {
namespace {

using google::protobuf::EnumDescriptor;
using google::protobuf::FieldDescriptor;
using google::protobuf::Message;
using google::protobuf::Reflection;

// --- Formatting ----------------------------------------------------------------

// Integers without decimals, floats with up to 6 significant digits, non-finite
// values spelled as in protobuf JSON.
template <typename T>
std::string Str(const T& value) {
  if constexpr (std::is_floating_point_v<T>) {
    if (std::isnan(value)) return "NaN";
    if (std::isinf(value)) return value > 0 ? "Infinity" : "-Infinity";
    char buffer[32];
    std::snprintf(buffer, sizeof buffer, "%.6g", static_cast<double>(value));
    return buffer;
  } else if constexpr (std::is_arithmetic_v<T>) {
    return std::to_string(value);
  } else {
    return std::string(value);
  }
}

std::string Str(const v1::Vec3& v);

template <typename... Parts>
std::string Cat(const Parts&... parts) {
  return (std::string() + ... + Str(parts));
}

std::string Str(const v1::Vec3& v) { return Cat("(", v.x(), ", ", v.y(), ", ", v.z(), ")"); }

// "KNIT_PATTERN_GARTER" -> "garter": enum values as spec authors think of them.
std::string ShortName(const EnumDescriptor* type, int number, std::string_view prefix) {
  const auto* value = type->FindValueByNumber(number);
  if (value == nullptr) return Str(number);
  std::string name = value->name().substr(prefix.size());
  std::transform(name.begin(), name.end(), name.begin(), [](unsigned char c) { return std::tolower(c); });
  return name;
}

// --- Small vector helpers ---------------------------------------------------------

using Named = std::pair<const char*, float>;

std::array<Named, 3> Channels(const v1::Rgb& c) { return {{{"r", c.r()}, {"g", c.g()}, {"b", c.b()}}}; }
std::array<Named, 3> Components(const v1::Vec3& v) { return {{{"x", v.x()}, {"y", v.y()}, {"z", v.z()}}}; }

bool IsZero(const v1::Vec3& v) { return v.x() == 0 && v.y() == 0 && v.z() == 0; }

// True when a and b (both non-zero) point along the same line.
bool IsParallel(const v1::Vec3& a, const v1::Vec3& b) {
  const double ax = a.x(), ay = a.y(), az = a.z(), bx = b.x(), by = b.y(), bz = b.z();
  const double cross = std::hypot(ay * bz - az * by, az * bx - ax * bz, ax * by - ay * bx);
  return cross <= 1e-6 * std::hypot(ax, ay, az) * std::hypot(bx, by, bz);
}

bool IsPowerOfTwo(uint32_t v) { return v != 0 && (v & (v - 1)) == 0; }

bool IsPerfectSquare(uint32_t v) {
  const auto root = static_cast<uint64_t>(std::llround(std::sqrt(static_cast<double>(v))));
  return root * root == v;
}

bool IsSha256Hex(const std::string& s) {
  return s.size() == 64 &&
         std::all_of(s.begin(), s.end(), [](char c) { return (c >= '0' && c <= '9') || (c >= 'a' && c <= 'f'); });
}

template <typename T>
bool IsFinite(T value) {
  if constexpr (std::is_floating_point_v<T>) return std::isfinite(value);
  return true;
}

// --- The collector ------------------------------------------------------------------

// Collects issues under one field path; Field() and Element() descend. Each rule
// is one call naming the field relative to this path, e.g.
//   at.Range("lobes", settings.lobes(), kMinLobes, kMaxLobes);
// Bounds skip non-finite values: CheckFiniteAndKnown reports those once.
class IssueCollector {
 public:
  IssueCollector(ValidationIssues* issues, std::string path) : issues_(issues), path_(std::move(path)) {}

  IssueCollector Field(std::string_view name) const { return {issues_, Join(name)}; }
  IssueCollector Element(std::string_view name, int index) const { return {issues_, Cat(Join(name), "[", index, "]")}; }

  void Report(std::string message) const { issues_->push_back({path_, std::move(message)}); }
  void Report(std::string_view field, std::string message) const { Field(field).Report(std::move(message)); }

  // Inclusive bounds: "<v> is below <min>", "<v> exceeds <max>". `note` explains
  // a bound that is not a plain number, e.g. "wales × courses".
  template <typename T>
  void Min(std::string_view field, T value, std::type_identity_t<T> min, std::string_view note = {}) const {
    if (IsFinite(value) && value < min) Report(field, Cat(value, " is below ", min) + Note(note));
  }
  template <typename T>
  void Max(std::string_view field, T value, std::type_identity_t<T> max, std::string_view note = {}) const {
    if (IsFinite(value) && value > max) Report(field, Cat(value, " exceeds ", max) + Note(note));
  }
  template <typename T>
  void Range(std::string_view field, T value, std::type_identity_t<T> min, std::type_identity_t<T> max) const {
    Min(field, value, min);
    Max(field, value, max);
  }

  // Exclusive bounds: "<v> is not above <min>", "<v> is not below <max>".
  template <typename T>
  void Above(std::string_view field, T value, std::type_identity_t<T> min, std::string_view note = {}) const {
    if (IsFinite(value) && !(value > min)) Report(field, Cat(value, " is not above ", min) + Note(note));
  }
  template <typename T>
  void Under(std::string_view field, T value, std::type_identity_t<T> max) const {
    if (IsFinite(value) && !(value < max)) Report(field, Cat(value, " is not below ", max));
  }

  // Every channel of a colour within [min, max].
  void Colour(std::string_view field, const v1::Rgb& rgb, float min,
              float max = std::numeric_limits<float>::infinity()) const {
    for (const auto& [channel, value] : Channels(rgb)) Field(field).Range(channel, value, min, max);
  }
  void Length(std::string_view field, const std::string& text, int max) const {
    if (text.size() > static_cast<size_t>(max)) Report(field, Cat("length ", text.size(), " exceeds ", max));
  }
  void PowerOfTwo(std::string_view field, uint32_t value, std::string_view why = {}) const {
    if (!IsPowerOfTwo(value)) Report(field, Cat(value, " is not a power of two") + Note(why));
  }
  // A count the GPU packs by fours (vec4s).
  void Multiple(std::string_view field, uint32_t value, uint32_t of) const {
    if (value % of != 0) Report(field, Cat(value, " is not a multiple of ", of));
  }
  void PerfectSquare(std::string_view field, uint32_t value, std::string_view why) const {
    if (!IsPerfectSquare(value)) Report(field, Cat(value, " is not a perfect square") + Note(why));
  }
  // A size the pattern does not use must stay 0.
  void Unused(std::string_view field, uint32_t value, std::string_view pattern, std::string_view users) const {
    if (value != 0) Report(field, Cat("must be 0 for ", pattern, " (only ", users, " use it)"));
  }
  // Each entry of a colour list indexes FabricSpec.yarns.
  void YarnIndices(std::string_view field, const google::protobuf::RepeatedField<uint32_t>& indices,
                   int yarn_count) const {
    const auto last = static_cast<uint32_t>(std::max(yarn_count, 1) - 1);
    for (int i = 0; i < indices.size(); ++i) Element(field, i).Max("", indices[i], last, "the last yarn index");
  }

 private:
  std::string Join(std::string_view name) const { return name.empty() ? path_ : Cat(path_, ".", name); }
  static std::string Note(std::string_view note) { return note.empty() ? "" : Cat(" (", note, ")"); }

  ValidationIssues* issues_;
  std::string path_;
};

// --- Rules that hold for every message --------------------------------------------

// Protobuf JSON accepts "NaN", "Infinity" and enum numbers, so every float must be
// checked for finiteness and every enum for a named value, wherever it sits.
void CheckFiniteAndKnown(const Message& message, const IssueCollector& at) {
  const Reflection* reflection = message.GetReflection();
  std::vector<const FieldDescriptor*> fields;
  reflection->ListFields(message, &fields);
  for (const FieldDescriptor* field : fields) {
    const bool repeated = field->is_repeated();
    const int count = repeated ? reflection->FieldSize(message, field) : 1;
    for (int i = 0; i < count; ++i) {
      const IssueCollector element = repeated ? at.Element(field->name(), i) : at.Field(field->name());
      auto finite = [&](double value) {
        if (!std::isfinite(value)) element.Report(Cat(value, " is not a finite number"));
      };
      switch (field->cpp_type()) {
        case FieldDescriptor::CPPTYPE_FLOAT:
          finite(repeated ? reflection->GetRepeatedFloat(message, field, i) : reflection->GetFloat(message, field));
          break;
        case FieldDescriptor::CPPTYPE_DOUBLE:
          finite(repeated ? reflection->GetRepeatedDouble(message, field, i) : reflection->GetDouble(message, field));
          break;
        case FieldDescriptor::CPPTYPE_ENUM: {
          const int number =
              repeated ? reflection->GetRepeatedEnumValue(message, field, i) : reflection->GetEnumValue(message, field);
          if (field->enum_type()->FindValueByNumber(number) == nullptr) {
            element.Report(Cat(number, " is not a known ", field->enum_type()->name(), " value"));
          }
          break;
        }
        case FieldDescriptor::CPPTYPE_MESSAGE:
          CheckFiniteAndKnown(
              repeated ? reflection->GetRepeatedMessage(message, field, i) : reflection->GetMessage(message, field),
              element);
          break;
        default:
          break;
      }
    }
  }
}

// --- PrecomputeSettings -------------------------------------------------------------

void CheckPrecompute(const v1::PrecomputeSettings& settings, const IssueCollector& at) {
  const uint32_t resolution = settings.spatial_resolution();
  at.Range("spatial_resolution", resolution, kMinSpatialResolution, kMaxSpatialResolution);
  at.PowerOfTwo("spatial_resolution", resolution, "mip levels halve the resolution");
  for (const auto& [field, count] : {std::pair{"view_directions", settings.view_directions()},
                                     std::pair{"light_directions", settings.light_directions()}}) {
    at.Range(field, count, kMinDirections, kMaxDirections);
    at.PerfectSquare(field, count, "directions lie on a k×k grid");
  }
  // Each factor within its own cap keeps the product exact in 64 bits; past a
  // cap the factor's own issue says enough.
  if (resolution <= kMaxSpatialResolution && settings.view_directions() <= kMaxDirections &&
      settings.light_directions() <= kMaxDirections) {
    const uint64_t samples =
        uint64_t{resolution} * resolution * settings.view_directions() * settings.light_directions();
    if (samples > kMaxRadianceSamples) {
      at.Report(Cat("spatial_resolution² × view_directions × light_directions = ", samples,
                    " radiance samples exceeds ", kMaxRadianceSamples));
    }
    // The table methods keep every sample per level while they build.
    if (IsTableMethod(settings.method()) && samples > kMaxTabulatedSamples) {
      at.Report(Cat("spatial_resolution² × view_directions × light_directions = ", samples,
                    " radiance samples exceeds ", kMaxTabulatedSamples,
                    ", the cap of the table methods (tabulated, factored, neural)"));
    }
  }
  at.Range("lobes", settings.lobes(), kMinLobes, kMaxLobes);
  at.Above("lut_change_threshold", settings.lut_change_threshold(), 0.0f);
  at.Max("lut_change_threshold", settings.lut_change_threshold(), kMaxLutChangeThreshold);
  at.Range("max_alternations", settings.max_alternations(), 1, kMaxAlternations);
  at.Range("max_lm_iterations", settings.max_lm_iterations(), 1, kMaxLmIterations);
  at.Max("indirect_bounces", settings.indirect_bounces(), kMaxIndirectBounces);
  at.Range("supersampling", settings.supersampling(), 1, kMaxSupersampling);
  if (settings.colour_components() && settings.indirect_bounces() != 0) {
    at.Report("colour_components", Cat("needs indirect_bounces 0, not ", settings.indirect_bounces(),
                                       ": light inter-reflected between yarns is not linear in their albedos"));
  }
  if (settings.method() == v1::FABRIC_METHOD_FACTORED) {
    at.Range("factored.rank", settings.factored().rank(), 1, kMaxFactoredRank);
  }
  if (settings.method() == v1::FABRIC_METHOD_NEURAL) {
    at.Range("neural.channels", settings.neural().channels(), 4, kMaxNeuralChannels);
    at.Multiple("neural.channels", settings.neural().channels(), 4);
    at.Range("neural.hidden", settings.neural().hidden(), 4, kMaxNeuralHidden);
    at.Multiple("neural.hidden", settings.neural().hidden(), 4);
    at.Range("neural.steps", settings.neural().steps(), 1, kMaxNeuralSteps);
    at.Max("neural.frequencies", settings.neural().frequencies(), kMaxNeuralFrequencies);
    at.Max("neural.base_rank", settings.neural().base_rank(), kMaxFactoredRank);
  }
}

// --- FabricSpec ----------------------------------------------------------------------

void CheckYarn(const v1::YarnSpec& yarn, bool knit, const IssueCollector& at) {
  at.Length("name", yarn.name(), kMaxNameLength);
  at.Above("radius", yarn.radius(), 0.0f);
  if (knit) {
    at.Max("radius", yarn.radius(), kMaxKnitYarnRadius, "for a knit: thicker yarns jam where loops interlock");
  } else {
    at.Max("radius", yarn.radius(), kMaxYarnRadius);
  }
  at.Range("plies", yarn.plies(), 1, kMaxPlies);
  at.Range("twist_degrees", yarn.twist_degrees(), -kMaxTwistDegrees, kMaxTwistDegrees);
  at.Range("fuzz", yarn.fuzz(), 0.0f, 1.0f);
  at.Colour("diffuse_albedo", yarn.diffuse_albedo(), 0, 1);
  at.Colour("specular_albedo", yarn.specular_albedo(), 0, 1);
  const auto diffuse = Channels(yarn.diffuse_albedo());
  const auto specular = Channels(yarn.specular_albedo());
  for (size_t c = 0; c < diffuse.size(); ++c) {
    const auto [channel, d] = diffuse[c];
    const float sum = d + specular[c].second;
    if (std::isfinite(sum) && sum > 1 + kAlbedoSumTolerance) {
      at.Report(Cat("diffuse_albedo.", channel, " + specular_albedo.", channel, " = ", sum,
                    " exceeds 1 (energy conservation)"));
    }
  }
  at.Above("roughness", yarn.roughness(), 0.0f);
  at.Max("roughness", yarn.roughness(), 1.0f);
  if (yarn.shading() == v1::YARN_SHADING_MICROFLAKE) {
    at.Range("height_scale", yarn.height_scale(), 0.0f, kMaxHeightScale);
    at.Range("lambert_blend", yarn.lambert_blend(), 0.0f, 1.0f);
    at.Range("diffuse_transmission", yarn.diffuse_transmission(), 0.0f, 1.0f);
  } else {
    for (const auto& [field, set] :
         {std::pair{"height_scale", yarn.has_height_scale()}, std::pair{"lambert_blend", yarn.has_lambert_blend()},
          std::pair{"diffuse_transmission", yarn.has_diffuse_transmission()}}) {
      if (set) at.Report(field, "only for shading YARN_SHADING_MICROFLAKE");
    }
  }
}

// Loops per tile side: within the cap and a whole number of pattern repeats.
void CheckLoopCount(const IssueCollector& at, std::string_view field, uint32_t count, uint32_t repeat,
                    const std::string& pattern) {
  at.Range(field, count, 1, kMaxLoopsPerTileSide);
  if (repeat > 1 && count % repeat != 0) {
    at.Report(field, Cat(count, " is not a multiple of ", repeat, " (the ", pattern, " pattern repeats every ", repeat,
                         " ", field, ")"));
  }
}

void CheckKnit(const v1::KnitSpec& knit, int yarn_count, const IssueCollector& at) {
  const std::string pattern = ShortName(v1::KnitPattern_descriptor(), knit.pattern(), "KNIT_PATTERN_");
  for (const auto& [field, width] : {std::pair{"rib_knit", knit.rib_knit()}, std::pair{"rib_purl", knit.rib_purl()}}) {
    if (knit.pattern() == v1::KNIT_PATTERN_RIB) {
      at.Range(field, width, 1, kMaxRibWidth);
    } else {
      at.Unused(field, width, pattern, "rib patterns");
    }
  }
  const KnitRepeat repeat = KnitPatternRepeat(knit);
  CheckLoopCount(at, "wales", knit.wales(), repeat.wales, pattern);
  CheckLoopCount(at, "courses", knit.courses(), repeat.courses, pattern);
  at.Range("loop_aspect", knit.loop_aspect(), kMinLoopAspect, kMaxLoopAspect);
  at.Range("loop_jitter", knit.loop_jitter(), 0.0f, kMaxLoopJitter);
  at.Max("colour_pattern", uint64_t(knit.colour_pattern_size()), uint64_t{knit.wales()} * knit.courses(),
         "wales × courses");
  at.YarnIndices("colour_pattern", knit.colour_pattern(), yarn_count);
}

void CheckWoven(const v1::WovenSpec& woven, int yarn_count, const IssueCollector& at) {
  const uint32_t n = woven.n(), m = woven.m();
  switch (woven.pattern()) {
    case v1::WEAVE_PATTERN_PLAIN:
      at.Unused("n", n, "plain", "twill, satin and basket weaves");
      at.Unused("m", m, "plain", "twill and satin weaves");
      break;
    case v1::WEAVE_PATTERN_TWILL:
      at.Range("n", n, kMinTwillFloat, kMaxTwillFloat);
      at.Range("m", m, kMinTwillFloat, kMaxTwillFloat);
      break;
    case v1::WEAVE_PATTERN_SATIN:
      at.Range("n", n, kMinSatinRepeat, kMaxSatinRepeat);
      if (n < kMinSatinRepeat || n > kMaxSatinRepeat) break;
      if (SmallestSatinMove(n) == 0) {
        at.Report("n", Cat(n, " has no valid satin move (no m with 1 < m < ", n - 1, " and gcd(m, ", n, ") = 1)"));
      } else if (!IsValidSatinMove(n, m)) {
        at.Report("m", Cat(m, " is not a valid satin move for n = ", n, " (need 1 < m < ", n - 1, " and gcd(m, ", n,
                           ") = 1)"));
      }
      break;
    case v1::WEAVE_PATTERN_BASKET:
      at.Range("n", n, kMinBasketGroup, kMaxBasketGroup);
      at.Unused("m", m, "basket", "twill and satin weaves");
      break;
    default:  // unknown values are reported by CheckFiniteAndKnown
      break;
  }
  at.Range("inclination_degrees", woven.inclination_degrees(), 0.0f, kMaxInclinationDegrees);
  at.Min("gap_ratio", woven.gap_ratio(), 0.0f);
  at.Under("gap_ratio", woven.gap_ratio(), kMaxGapRatio);
  for (const auto& [field, colours] :
       {std::pair{"warp_colours", &woven.warp_colours()}, std::pair{"weft_colours", &woven.weft_colours()}}) {
    at.Max(field, colours->size(), kMaxColourListLength);
    at.YarnIndices(field, *colours, yarn_count);
  }
}

void CheckFabric(const v1::FabricSpec& fabric, const IssueCollector& at) {
  at.Length("name", fabric.name(), kMaxNameLength);
  if (fabric.structure_case() == v1::FabricSpec::STRUCTURE_NOT_SET) {
    // Yarn sizes are fractions of the loop width or yarn pitch: nothing more to check.
    at.Report("one of knit or woven is required");
    return;
  }
  at.Range("yarns", fabric.yarns_size(), kMinYarns, kMaxYarns);
  for (int i = 0; i < fabric.yarns_size(); ++i) CheckYarn(fabric.yarns(i), fabric.has_knit(), at.Element("yarns", i));
  if (fabric.has_knit()) {
    CheckKnit(fabric.knit(), fabric.yarns_size(), at.Field("knit"));
  } else {
    CheckWoven(fabric.woven(), fabric.yarns_size(), at.Field("woven"));
  }
}

// --- RenderSettings --------------------------------------------------------------------

void CheckRender(const v1::RenderSettings& settings, const IssueCollector& at) {
  switch (settings.method()) {
    case v1::RENDER_METHOD_NEURAL:
    case v1::RENDER_METHOD_AUTO:
      at.Report("method", Cat(v1::RenderMethod_Name(settings.method()), " is not implemented yet (roadmap)"));
      break;
    default:
      break;
  }
  at.Range("width", settings.width(), 1, kMaxImageSide);
  at.Range("height", settings.height(), 1, kMaxImageSide);
  const uint64_t pixels = uint64_t{settings.width()} * settings.height();
  if (pixels > kMaxImagePixels) at.Report(Cat("width × height = ", pixels, " pixels exceeds ", kMaxImagePixels));
  if (!IsPowerOfTwo(settings.msaa_samples()) || settings.msaa_samples() > kMaxMsaaSamples) {
    std::string allowed = "1";
    for (uint32_t samples = 2; samples <= kMaxMsaaSamples; samples *= 2) allowed += Cat(", ", samples);
    at.Report("msaa_samples", Cat(settings.msaa_samples(), " is not one of ", allowed));
  }
  at.Range("shadow_map_size", settings.shadow_map_size(), kMinShadowMapSize, kMaxShadowMapSize);
  at.PowerOfTwo("shadow_map_size", settings.shadow_map_size());
  at.Range("reference_samples", settings.reference_samples(), 1, kMaxReferenceSamples);
  at.Range("lod_bias", settings.lod_bias(), -kMaxLodBias, kMaxLodBias);
}

// --- SceneSpec ------------------------------------------------------------------------

void CheckMesh(const v1::MeshRef& mesh, const IssueCollector& at) {
  switch (mesh.source_case()) {
    case v1::MeshRef::kBuiltin:
      if (mesh.builtin() == v1::BUILTIN_SHAPE_UNSPECIFIED)
        at.Report("builtin", "BUILTIN_SHAPE_UNSPECIFIED is not a shape");
      break;
    case v1::MeshRef::kObjPath:
      if (mesh.obj_path().empty()) at.Report("obj_path", "is empty");
      at.Length("obj_path", mesh.obj_path(), kMaxPathLength);
      break;
    case v1::MeshRef::kGltfPath:
      if (mesh.gltf_path().empty()) at.Report("gltf_path", "is empty");
      at.Length("gltf_path", mesh.gltf_path(), kMaxPathLength);
      break;
    case v1::MeshRef::kArtifact:
      if (!IsSha256Hex(mesh.artifact())) at.Report("artifact", "is not a content hash (64 lowercase hex digits)");
      break;
    case v1::MeshRef::SOURCE_NOT_SET:
      at.Report("one of builtin, obj_path, gltf_path or artifact is required");
      break;
  }
  at.Max("frame", mesh.frame(), kMaxAnimationFrames);
  if (mesh.frame() > 0 &&
      (mesh.source_case() == v1::MeshRef::kBuiltin || mesh.source_case() == v1::MeshRef::kObjPath)) {
    at.Report("frame", "applies to glTF mesh sequences only");
  }
  at.Length("gltf_mesh", mesh.gltf_mesh(), kMaxNameLength);
  if (!mesh.gltf_mesh().empty() &&
      (mesh.source_case() == v1::MeshRef::kBuiltin || mesh.source_case() == v1::MeshRef::kObjPath)) {
    at.Report("gltf_mesh", "applies to glTF meshes only");
  }
  at.Max("segments", mesh.segments(), kMaxSegments);
}

void CheckBinding(const v1::FabricBinding& binding, const IssueCollector& at) {
  CheckFabric(binding.fabric(), at.Field("fabric"));
  if (binding.has_precompute()) CheckPrecompute(binding.precompute(), at.Field("precompute"));
  for (const auto& [field, repeat] :
       {std::pair{"repeat_u", binding.repeat_u()}, std::pair{"repeat_v", binding.repeat_v()}}) {
    at.Above(field, repeat, 0.0f);
    at.Max(field, repeat, kMaxRepeat);
  }
}

void CheckTransformScale(const v1::Transform& transform, const IssueCollector& at) {
  for (const auto& [axis, scale] : Components(transform.scale())) {
    if (scale == 0) at.Field("transform.scale").Report(axis, "must not be zero (a zero scale flattens the object)");
  }
}

void CheckObject(const v1::SceneObject& object, const IssueCollector& at) {
  at.Length("name", object.name(), kMaxNameLength);
  CheckMesh(object.mesh(), at.Field("mesh"));
  CheckTransformScale(object.transform(), at);
  if (object.has_fabric()) CheckBinding(object.fabric(), at.Field("fabric"));
  at.Colour("base_colour", object.base_colour(), 0, 1);
}

void CheckCamera(const v1::Camera& camera, const IssueCollector& at) {
  v1::Vec3 view;
  view.set_x(camera.target().x() - camera.position().x());
  view.set_y(camera.target().y() - camera.position().y());
  view.set_z(camera.target().z() - camera.position().z());
  if (IsZero(view)) {
    at.Report("target", "equals position (the camera needs a view direction)");
  } else if (IsParallel(camera.up(), view)) {
    at.Report("up", Cat(camera.up(), " is parallel to the view direction ", view));
  }
  at.Above("fov_y_degrees", camera.fov_y_degrees(), 0.0f);
  at.Under("fov_y_degrees", camera.fov_y_degrees(), kMaxFovDegrees);
  at.Above("ortho_height", camera.ortho_height(), 0.0f);
  at.Above("near", camera.near(), 0.0f);
  at.Above("far", camera.far(), camera.near(), "near");
}

void CheckLight(const v1::Light& light, const IssueCollector& at) {
  if (light.type() == v1::LIGHT_TYPE_DIRECTIONAL && IsZero(light.direction())) {
    at.Report("direction", "is zero (a directional light needs a direction)");
  }
  at.Colour("colour", light.colour(), 0);
  at.Min("intensity", light.intensity(), 0.0f);
}

void CheckScene(const v1::SceneSpec& scene, const IssueCollector& at) {
  at.Length("name", scene.name(), kMaxNameLength);
  at.Range("objects", scene.objects_size(), kMinObjects, kMaxObjects);
  for (int i = 0; i < scene.objects_size(); ++i) CheckObject(scene.objects(i), at.Element("objects", i));
  CheckCamera(scene.camera(), at.Field("camera"));
  at.Max("lights", scene.lights_size(), kMaxLights);
  for (int i = 0; i < scene.lights_size(); ++i) CheckLight(scene.lights(i), at.Element("lights", i));
  at.Colour("ambient", scene.ambient(), 0);
  at.Colour("background", scene.background(), 0);
  CheckRender(scene.render(), at.Field("render"));
  if (scene.render().method() == v1::RENDER_METHOD_LUMISLICE) {
    const uint64_t grid = LumisliceRayGrid(scene.render().msaa_samples());
    const uint64_t width = grid * scene.render().width(), height = grid * scene.render().height();
    if (grid > 1 && (width > kMaxImageSide || height > kMaxImageSide || width * height > kMaxImagePixels)) {
      at.Field("render").Report("msaa_samples",
                                Cat(scene.render().msaa_samples(), " rays a pixel (", grid, " × ", grid,
                                    ") make RENDER_METHOD_LUMISLICE render ", width, " × ", height, " pixels: at most ",
                                    kMaxImageSide, " a side and ", kMaxImagePixels, " in all"));
    }
    for (int i = 0; i < scene.objects_size(); ++i) {
      const v1::SceneObject& object = scene.objects(i);
      if (object.has_fabric() && !object.fabric().fabric().has_knit()) {
        at.Element("objects", i).Field("fabric").Report("fabric", "RENDER_METHOD_LUMISLICE renders knit fabrics only");
      }
    }
  }
}

// --- AnimationSpec ------------------------------------------------------------------

void CheckCoordinates(const IssueCollector& at, std::string_view field, const v1::Vec3& v, float bound) {
  for (const auto& [component, value] : Components(v)) at.Field(field).Range(component, value, -bound, bound);
}

void CheckMotion(const google::protobuf::RepeatedPtrField<v1::LinearMotion>& legs, float duration,
                 const IssueCollector& at) {
  at.Max("motion", legs.size(), kMaxMotionLegs);
  for (int i = 0; i < legs.size(); ++i) {
    const IssueCollector leg = at.Element("motion", i);
    CheckCoordinates(leg, "velocity", legs[i].velocity(), kMaxAnimationSpeed);
    leg.Min("start_seconds", legs[i].start_seconds(), 0.0f);
    leg.Min("end_seconds", legs[i].end_seconds(), legs[i].start_seconds(), "start_seconds");
    leg.Max("end_seconds", legs[i].end_seconds(), duration, "duration_seconds");
  }
}

void CheckCloth(const v1::KnitClothSpec& cloth, const IssueCollector& at) {
  at.Range("loops", cloth.loops(), kMinClothLoops, kMaxClothLoops);
  at.Range("courses", cloth.courses(), kMinClothLoops, kMaxClothLoops);
  at.Max("courses", uint64_t{cloth.loops()} * cloth.courses(), kMaxClothPoints, "loops × courses");
  for (const auto& [field, spacing] :
       {std::pair{"course_spacing", cloth.course_spacing()}, std::pair{"wale_spacing", cloth.wale_spacing()}}) {
    at.Above(field, spacing, 0.0f);
    at.Max(field, spacing, kMaxLoopSpacing);
  }
  CheckCoordinates(at, "origin", cloth.origin(), kMaxAnimationCoordinate);
  if (IsParallel(cloth.course_axis(), cloth.wale_axis())) {
    at.Report("wale_axis", Cat(cloth.wale_axis(), " is parallel to course_axis ", cloth.course_axis()));
  }
  if (cloth.has_fabric()) {
    CheckFabric(cloth.fabric(), at.Field("fabric"));
    if (!cloth.fabric().has_knit()) at.Report("fabric", "must be a knit fabric (the cloth is knitted)");
  }
}

void CheckPins(const v1::AnimationSpec& animation, const IssueCollector& at) {
  const uint32_t loops = animation.cloth().loops(), courses = animation.cloth().courses();
  at.Max("pins", animation.pins_size(), kMaxPins);
  if (animation.pins_size() > kMaxPins || uint64_t{loops} * courses > kMaxClothPoints) return;
  std::vector<int> pinned_by(static_cast<size_t>(loops) * courses, -1);
  for (int i = 0; i < animation.pins_size(); ++i) {
    const v1::PinSpec& pin = animation.pins(i);
    const IssueCollector element = at.Element("pins", i);
    std::vector<std::pair<uint32_t, uint32_t>> held;  // (loop, course)
    switch (pin.which_case()) {
      case v1::PinSpec::kLoop:
        element.Field("loop").Max("loop", pin.loop().loop(), loops - 1, "cloth.loops − 1");
        element.Field("loop").Max("course", pin.loop().course(), courses - 1, "cloth.courses − 1");
        held.emplace_back(pin.loop().loop(), pin.loop().course());
        break;
      case v1::PinSpec::kCourse:
        element.Max("course", pin.course(), courses - 1, "cloth.courses − 1");
        for (uint32_t l = 0; l < loops; ++l) held.emplace_back(l, pin.course());
        break;
      case v1::PinSpec::kWale:
        element.Max("wale", pin.wale(), loops - 1, "cloth.loops − 1");
        for (uint32_t c = 0; c < courses; ++c) held.emplace_back(pin.wale(), c);
        break;
      default:
        element.Report("names no loop, course or wale");
    }
    CheckMotion(pin.motion(), animation.duration_seconds(), element);
    element.Min("release_seconds", pin.release_seconds(), 0.0f);
    element.Max("release_seconds", pin.release_seconds(), animation.duration_seconds(), "duration_seconds");
    for (const auto& [loop, course] : held) {
      if (loop >= loops || course >= courses) continue;
      int& by = pinned_by[static_cast<size_t>(course) * loops + loop];
      if (by >= 0) {
        element.Report(Cat("pins loop (", loop, ", ", course, "), which pins[", by, "] pins already"));
        break;
      }
      by = i;
    }
  }
}

void CheckCollider(const v1::ColliderSpec& collider, float duration, const IssueCollector& at) {
  switch (collider.shape_case()) {
    case v1::ColliderSpec::kPlane:
      CheckCoordinates(at.Field("plane"), "point", collider.plane().point(), kMaxAnimationCoordinate);
      if (IsZero(collider.plane().normal())) at.Field("plane").Report("normal", "is zero");
      break;
    case v1::ColliderSpec::kSphere:
      CheckCoordinates(at.Field("sphere"), "centre", collider.sphere().centre(), kMaxAnimationCoordinate);
      at.Field("sphere").Above("radius", collider.sphere().radius(), 0.0f);
      at.Field("sphere").Max("radius", collider.sphere().radius(), kMaxColliderSize);
      at.Field("sphere").Min("mass", collider.sphere().mass(), 0.0f);
      at.Field("sphere").Max("mass", collider.sphere().mass(), kMaxBallMass);
      at.Field("sphere").Min("release_seconds", collider.sphere().release_seconds(), 0.0f);
      at.Field("sphere").Max("release_seconds", collider.sphere().release_seconds(), duration, "duration_seconds");
      if (collider.sphere().release_seconds() > 0.0f && collider.sphere().mass() == 0.0f) {
        at.Field("sphere").Report("release_seconds", "lets go a sphere without a mass (set mass)");
      }
      break;
    case v1::ColliderSpec::kBox:
      CheckCoordinates(at.Field("box"), "centre", collider.box().centre(), kMaxAnimationCoordinate);
      for (const auto& [component, value] : Components(collider.box().half_extent())) {
        at.Field("box").Field("half_extent").Above(component, value, 0.0f);
        at.Field("box").Field("half_extent").Max(component, value, kMaxColliderSize);
      }
      break;
    case v1::ColliderSpec::kMesh:
      CheckMesh(collider.mesh().mesh(), at.Field("mesh").Field("mesh"));
      CheckTransformScale(collider.mesh().transform(), at.Field("mesh"));
      break;
    default:
      at.Report("names no plane, sphere, box or mesh");
  }
  CheckMotion(collider.motion(), duration, at);
}

void CheckMechanics(const v1::KnitMechanicsSpec& mechanics, const IssueCollector& at) {
  at.Range("contact_damping", mechanics.contact_damping(), 0.0f, kMaxContactDamping);
  at.Range("static_friction", mechanics.static_friction(), 0.0f, kMaxFriction);
  at.Range("dynamic_friction", mechanics.dynamic_friction(), 0.0f, kMaxFriction);
  at.Range("air_viscosity", mechanics.air_viscosity(), 0.0f, kMaxAirViscosity);
  if (mechanics.has_courant()) {
    at.Above("courant", mechanics.courant(), 0.0f);
    at.Max("courant", mechanics.courant(), kMaxCourant);
  }
}

void CheckAnimation(const v1::AnimationSpec& animation, const IssueCollector& at) {
  at.Length("name", animation.name(), kMaxNameLength);
  CheckCloth(animation.cloth(), at.Field("cloth"));
  at.Above("duration_seconds", animation.duration_seconds(), 0.0f);
  at.Max("duration_seconds", animation.duration_seconds(), kMaxAnimationSeconds);
  at.Above("frames_per_second", animation.frames_per_second(), 0.0f);
  at.Max("frames_per_second", animation.frames_per_second(), kMaxFramesPerSecond);
  if (const uint64_t frames = AnimationFrames(animation); frames > kMaxAnimationFrames) {
    at.Report("frames_per_second",
              Cat(animation.frames_per_second(), " frames a second for ", animation.duration_seconds(), " s make ",
                  frames, " frames; at most ", kMaxAnimationFrames));
  } else if (const uint64_t points = (frames + 1) * animation.cloth().loops() * animation.cloth().courses();
             points > kMaxAnimationPoints) {
    at.Report("duration_seconds",
              Cat(frames + 1, " frames of ", animation.cloth().loops(), " × ", animation.cloth().courses(),
                  " loops make ", points, " points; at most ", kMaxAnimationPoints));
  }
  CheckCoordinates(at, "initial_velocity", animation.initial_velocity(), kMaxAnimationSpeed);
  CheckMechanics(animation.mechanics(), at.Field("mechanics"));
  CheckPins(animation, at);
  at.Max("colliders", animation.colliders_size(), kMaxColliders);
  for (int i = 0; i < animation.colliders_size(); ++i) {
    CheckCollider(animation.colliders(i), animation.duration_seconds(), at.Element("colliders", i));
  }
}

// Defaults first (zero means default), then the generic rules, then the spec's own.
template <typename Spec>
ValidationIssues ValidateWith(const Spec& spec, const std::string& root,
                              void (*check)(const Spec&, const IssueCollector&)) {
  ValidationIssues issues;
  const IssueCollector at(&issues, root);
  const Spec full = WithDefaults(spec);
  CheckFiniteAndKnown(full, at);
  check(full, at);
  return issues;
}

}  // namespace

ValidationIssues Validate(const v1::FabricSpec& fabric, const std::string& root) {
  return ValidateWith(fabric, root, CheckFabric);
}

ValidationIssues Validate(const v1::PrecomputeSettings& settings, const std::string& root) {
  return ValidateWith(settings, root, CheckPrecompute);
}

ValidationIssues Validate(const v1::FabricSpec& fabric, const v1::PrecomputeSettings& settings) {
  ValidationIssues issues = Validate(fabric);
  const ValidationIssues settings_issues = Validate(settings);
  issues.insert(issues.end(), settings_issues.begin(), settings_issues.end());
  return issues;
}

ValidationIssues Validate(const v1::RenderSettings& settings, const std::string& root) {
  return ValidateWith(settings, root, CheckRender);
}

ValidationIssues Validate(const v1::SceneSpec& scene, const std::string& root) {
  return ValidateWith(scene, root, CheckScene);
}

ValidationIssues Validate(const v1::AnimationSpec& animation, const std::string& root) {
  return ValidateWith(animation, root, CheckAnimation);
}

std::string FormatIssues(const ValidationIssues& issues) {
  std::string text;
  for (const ValidationIssue& issue : issues) {
    if (!text.empty()) text += '\n';
    text += issue.ToString();
  }
  return text;
}

void ThrowIfAny(const ValidationIssues& issues) {
  if (!issues.empty()) throw Error(ErrorCode::kInvalidArgument, FormatIssues(issues));
}

}  // namespace loom
