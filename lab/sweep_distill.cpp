#include "lab/sweep_distill.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <limits>
#include <map>
#include <set>
#include <utility>

#include "core/methods/fabric_method.h"
#include "core/spec/defaults.h"
#include "core/util/error.h"
#include "lab/sweep_results.h"

namespace loom::lab {
namespace {

struct Measured {
  double footprint = NAN;
  FabricKind kind = FabricKind::kKnitMatte;
  double psnr = NAN, precompute = NAN, bytes = NAN;
  std::string method, method_settings, resolution, directions, lights, lobes, lookup_table, supersampling,
      sampling_plane, level_mode, texel_filter, msaa, lod_bias, shading_rate, seed;
};

double ToNumber(const std::string& field) { return field.empty() ? NAN : std::stod(field); }

// What a row was fitted and rendered with, as far as the CSV says, its seed left out.
std::string Settings(const Measured& m) {
  return m.method + ',' + m.method_settings + ',' + m.resolution + ',' + m.directions + ',' + m.lights + ',' + m.lobes + ',' + m.lookup_table + ',' +
         m.supersampling + ',' + m.sampling_plane + ',' + m.level_mode + ',' + m.texel_filter + ',' + m.msaa + ',' + m.lod_bias + ',' + m.shading_rate;
}

// Every row takes the mean figures over the seeds measured on its scene with its
// settings (see the header). A seed measured twice (the defaults are in the sweep
// and in its repeats) counts once.
void AverageRepeats(std::map<std::string, std::map<std::string, Measured>>& rows) {
  // (scene, settings) → seed → a row of it
  std::map<std::pair<std::string, std::string>, std::map<std::string, const Measured*>> repeats;
  for (const auto& [configuration, scenes] : rows) {
    for (const auto& [scene, m] : scenes) repeats[{scene, Settings(m)}].emplace(m.seed, &m);
  }
  struct Means {
    double psnr = 0, precompute = 0, bytes = 0;
  };
  std::map<std::pair<std::string, std::string>, Means> means;
  for (const auto& [key, by_seed] : repeats) {
    Means& mean = means[key];
    for (const auto& [seed, m] : by_seed) {
      mean.psnr += m->psnr / by_seed.size();
      mean.precompute += m->precompute / by_seed.size();
      mean.bytes += m->bytes / by_seed.size();
    }
  }
  for (auto& [configuration, scenes] : rows) {
    for (auto& [scene, m] : scenes) {
      const Means& mean = means.at({scene, Settings(m)});
      m.psnr = mean.psnr;
      m.precompute = mean.precompute;
      m.bytes = mean.bytes;
    }
  }
}

// A configuration of another method than the baseline's, at that method's defaults
// with the baseline's resolution, lights and supersampling: the method (else
// unspecified). Its views and sampling plane are the method's defaults (the table
// methods' 9×9 and view-depth planes).
v1::FabricMethod MethodVariation(const Measured& m, const Measured& b) {
  const FabricMethod* method = MethodNamed(m.method);
  if (method == nullptr || m.method == b.method) return v1::FABRIC_METHOD_UNSPECIFIED;
  v1::PrecomputeSettings own;
  own.set_method(method->id());
  own = WithDefaults(own);
  const bool defaults = m.resolution == b.resolution && m.lights == b.lights &&
                        m.supersampling == b.supersampling &&
                        m.directions == std::to_string(own.view_directions()) &&
                        m.sampling_plane == SamplingPlaneColumn(own.sampling_plane()) &&
                        m.method_settings == method->OwnSettings(own);
  return defaults ? method->id() : v1::FABRIC_METHOD_UNSPECIFIED;
}

FabricKind ToKind(const std::string& field, const std::string& scene) {
  const std::optional<FabricKind> kind = ParseFabricKind(field);
  if (!kind) {
    throw Error(ErrorCode::kInvalidArgument, "sweep CSV, scene " + scene + ": fabric_kind '" + field +
                                                 "' is not one of knit-matte, knit-glossy, woven-matte, woven-glossy");
  }
  return *kind;
}

}  // namespace

std::vector<MeasuredVariation> DistillSweep(const CsvTable& table, const std::string& baseline) {
  const auto column = [&](const char* name) { return table.Column(name); };
  // A column older sweeps lack: what every row of them had.
  const auto optional_column = [&](const char* name, std::string before) {
    const auto found = std::find(table.columns.begin(), table.columns.end(), name);
    return [found, before, &table](const std::vector<std::string>& row) {
      return found == table.columns.end() ? before : row[size_t(found - table.columns.begin())];
    };
  };
  // Sweeps before fabric methods had no method settings, before sampling planes the
  // top face, before shading rates one shading a pixel.
  const auto own_settings = optional_column("method_settings", "");
  const auto sampling_plane = optional_column("sampling_plane", kSamplingPlaneBeforeTheColumn);
  const auto shading_rate = optional_column("shading_rate", kShadingRateBeforeTheColumn);
  const size_t configuration = column("configuration"), scene = column("scene"), method = column("method"),
               footprint = column("footprint_pixels"), kind = column("fabric_kind"), psnr = column("psnr_db"), precompute = column("precompute_cpu_seconds"),
               bytes = column("asset_bytes"), resolution = column("spatial_resolution"),
               views = column("view_directions"), lights = column("light_directions"), lobes = column("lobes"),
               lut = column("lookup_table"), supersampling = column("supersampling"), level = column("level_mode"),
               filter = column("texel_filter"), msaa = column("msaa_samples"), lod_bias = column("lod_bias"),
               seed = column("seed");
  // configuration → scene → figures, in order of first appearance.
  std::vector<std::string> order;
  std::map<std::string, std::map<std::string, Measured>> rows;
  for (const auto& row : table.rows) {
    if (MethodNamed(row[method]) == nullptr) continue;  // the reference
    if (!rows.contains(row[configuration])) order.push_back(row[configuration]);
    rows[row[configuration]][row[scene]] = {ToNumber(row[footprint]), ToKind(row[kind], row[scene]),
                                            ToNumber(row[psnr]), ToNumber(row[precompute]),
                                            ToNumber(row[bytes]), row[method], own_settings(row),
                                            row[resolution], row[views],
                                            row[lights],        row[lobes],         row[lut],
                                            row[supersampling], sampling_plane(row), row[level], row[filter],
                                            row[msaa],          row[lod_bias],      shading_rate(row),
                                            row[seed]};
  }
  AverageRepeats(rows);
  if (!rows.contains(baseline)) {
    throw Error(ErrorCode::kInvalidArgument, "sweep CSV has no GPU rows of the baseline configuration '" +
                                                 baseline + "'");
  }
  const auto& base = rows.at(baseline);
  // The figures are changes against the baseline as rendered: the planner applies
  // them to the default render, so a baseline rendered otherwise (a sweep measured
  // before the defaults changed) would describe another renderer.
  const RenderColumns default_render = SweepRenderColumns(WithDefaults(v1::RenderSettings()));
  for (const auto& [scene_name, b] : base) {
    const RenderColumns rendered{b.level_mode, b.texel_filter, b.msaa, b.lod_bias, b.shading_rate};
    if (rendered == default_render) continue;
    const auto describe = [](const RenderColumns& r) {
      return "level_mode " + r.level_mode + ", texel_filter " + r.texel_filter + ", msaa_samples " + r.msaa_samples +
             ", lod_bias " + r.lod_bias + ", shading_rate " + r.shading_rate;
    };
    throw Error(ErrorCode::kInvalidArgument, "sweep CSV: the baseline '" + baseline + "' on scene " + scene_name +
                                                 " was rendered with " + describe(rendered) +
                                                 ", but the default render is " + describe(default_render) +
                                                 ": render the sweep's svbrdf rows again with the defaults");
  }
  // So with the plane acquisition samples on: the baseline's must be the default's.
  const std::string default_plane = SamplingPlaneColumn(WithDefaults(v1::PrecomputeSettings()).sampling_plane());
  for (const auto& [scene_name, b] : base) {
    if (b.sampling_plane == default_plane) continue;
    throw Error(ErrorCode::kInvalidArgument, "sweep CSV: the baseline '" + baseline + "' on scene " + scene_name +
                                                 " was acquired with sampling plane " + b.sampling_plane +
                                                 ", but the default is " + default_plane +
                                                 ": measure the sweep again with the defaults");
  }
  using SceneClass = std::pair<FootprintClass, FabricKind>;
  std::map<SceneClass, int> base_scenes;
  for (const auto& [scene_name, b] : base) ++base_scenes[{ClassifyFootprint(b.footprint), b.kind}];
  std::vector<MeasuredVariation> variations;
  // A configuration all of whose rows repeat an earlier one's (the same scene and
  // settings under another seed) is in that one's figures already.
  std::set<std::pair<std::string, std::string>> measured;  // (scene, settings)
  for (const auto& [scene_name, b] : base) measured.insert({scene_name, Settings(b)});
  for (const std::string& name : order) {
    if (name == baseline) continue;
    bool repeat = true;
    for (const auto& [scene_name, m] : rows.at(name)) repeat &= !measured.insert({scene_name, Settings(m)}).second;
    if (repeat) continue;
    struct Sums {
      double psnr_change = 0, precompute = 0, base_precompute = 0, bytes = 0, base_bytes = 0;
      double worst_psnr_change = std::numeric_limits<double>::infinity();
      int scenes = 0;
    };
    std::map<SceneClass, Sums> by_class;
    std::map<SceneClass, int> covered;  // scenes measured, NaN images included
    MeasuredVariation variation;
    variation.configuration = name;
    bool single_change = true;
    for (const auto& [scene_name, m] : rows.at(name)) {
      const auto found = base.find(scene_name);
      if (found == base.end()) continue;
      const Measured& b = found->second;
      if (m.level_mode != b.level_mode || m.texel_filter != b.texel_filter || m.msaa != b.msaa ||
          m.lod_bias != b.lod_bias || m.shading_rate != b.shading_rate) {
        single_change = false;  // renders differently: not a precompute variation
        break;
      }
      MeasuredVariation v;
      int axes = 0;
      if (m.method != b.method) {
        // Another method at its own defaults, or a combination the planner never makes.
        v.method = MethodVariation(m, b);
        axes = v.method == v1::FABRIC_METHOD_UNSPECIFIED ? 2 : 1;
      } else {
        if (m.resolution != b.resolution) v.spatial_resolution = std::stoul(m.resolution), ++axes;
        if (m.directions != b.directions || m.lights != b.lights) {
          if (m.directions != m.lights) axes += 2;  // unequal views and lights: not one the planner sets
          v.directions = std::stoul(m.directions), ++axes;
        }
        if (m.lobes != b.lobes) v.lobes = std::stoul(m.lobes), ++axes;
        if (m.lookup_table != b.lookup_table) v.lookup_table = m.lookup_table == "1" ? 1 : 0, ++axes;
        if (m.supersampling != b.supersampling) {
          v.supersampling = std::stoul(m.supersampling);
          if (v.spatial_resolution == 0) axes += 2;  // alone it is not a setting the planner varies
        }
        if (m.sampling_plane != b.sampling_plane) axes += 2;  // not a setting the planner varies
      }
      const bool same_as_before = by_class.empty() ||
                                  (v.method == variation.method && v.spatial_resolution == variation.spatial_resolution &&
                                   v.directions == variation.directions && v.lobes == variation.lobes &&
                                   v.lookup_table == variation.lookup_table &&
                                   v.supersampling == variation.supersampling);
      if (axes != 1 || !same_as_before) {  // a combination, or a plan (settings vary by scene)
        single_change = false;
        break;
      }
      variation.method = v.method;
      variation.spatial_resolution = v.spatial_resolution;
      variation.directions = v.directions;
      variation.lobes = v.lobes;
      variation.lookup_table = v.lookup_table;
      variation.supersampling = v.supersampling;
      ++covered[{ClassifyFootprint(b.footprint), b.kind}];
      // A NaN image (PSNR nan or +inf, docs/results "Known problems") says nothing
      // about accuracy: left out, as the chart leaves it out.
      if (!std::isfinite(m.psnr) || !std::isfinite(b.psnr)) continue;
      Sums& sums = by_class[{ClassifyFootprint(b.footprint), b.kind}];
      sums.psnr_change += m.psnr - b.psnr;
      sums.worst_psnr_change = std::min(sums.worst_psnr_change, m.psnr - b.psnr);
      sums.precompute += m.precompute;
      sums.base_precompute += b.precompute;
      sums.bytes += m.bytes;
      sums.base_bytes += b.bytes;
      ++sums.scenes;
    }
    if (!single_change) continue;
    for (const auto& [scene_class, sums] : by_class) {
      // Only where the variation ran on every scene of the class the baseline ran
      // on: a worst case over some of the class is no worst case.
      if (covered[scene_class] < base_scenes[scene_class]) continue;
      MeasuredVariation v = variation;
      v.footprint = scene_class.first;
      v.fabric_kind = scene_class.second;
      v.psnr_change_db = sums.psnr_change / sums.scenes;
      v.worst_psnr_change_db = sums.worst_psnr_change;
      v.precompute_ratio = sums.base_precompute > 0 ? sums.precompute / sums.base_precompute : 1.0;
      v.bytes_ratio = sums.base_bytes > 0 ? sums.bytes / sums.base_bytes : 1.0;
      v.scenes = sums.scenes;
      variations.push_back(v);
    }
  }
  return variations;
}

std::string VariationsAsCpp(const std::vector<MeasuredVariation>& variations) {
  static const char* kClass[] = {"kNear", "kMid", "kFar"};
  static const char* kKind[] = {"kKnitMatte", "kKnitGlossy", "kWovenMatte", "kWovenGlossy"};
  std::string text =
      "// {configuration, footprint class, fabric kind, spatial_resolution, directions, lobes, lookup_table, "
      "supersampling,\n//  mean PSNR change dB, worst PSNR change dB, precompute CPU-time ratio, bytes ratio, "
      "scenes, method}\n";
  for (const MeasuredVariation& v : variations) {
    char line[512];
    std::snprintf(line, sizeof line,
                  "    {\"%s\", FootprintClass::%s, FabricKind::%s, %u, %u, %u, %d, %u, %.3f, %.3f, %.4f, %.4f, %d, "
                  "v1::%s},\n",
                  v.configuration.c_str(), kClass[static_cast<int>(v.footprint)],
                  kKind[static_cast<int>(v.fabric_kind)], v.spatial_resolution, v.directions, v.lobes,
                  v.lookup_table, v.supersampling, v.psnr_change_db, v.worst_psnr_change_db, v.precompute_ratio,
                  v.bytes_ratio, v.scenes, v1::FabricMethod_Name(v.method).c_str());
    text += line;
  }
  return text;
}

}  // namespace loom::lab
