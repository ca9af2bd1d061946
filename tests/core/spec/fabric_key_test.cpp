#include "core/spec/fabric_key.h"

#include <gtest/gtest.h>

#include <functional>

#include "core/acquire/volume_radiance.h"
#include "core/spec/defaults.h"
#include "core/spec/spec_json.h"

namespace loom {
namespace {

using google::protobuf::FieldDescriptor;
using google::protobuf::Message;
using google::protobuf::Reflection;

v1::FabricSpec Fabric(const char* json) { return ParseSpecJson<v1::FabricSpec>(json, "fabric"); }
v1::PrecomputeSettings Settings(const char* json) { return ParseSpecJson<v1::PrecomputeSettings>(json, "precompute"); }

TEST(FabricKey, IsStableUnderFieldOrder) {
  const auto a = Fabric(R"({"knit": {"pattern": "KNIT_PATTERN_RIB", "rib_knit": 2, "rib_purl": 2},
                            "yarns": [{"radius": 0.12, "diffuse_albedo": {"r": 0.8, "g": 0.1, "b": 0.1}}]})");
  const auto b = Fabric(R"({"yarns": [{"diffuse_albedo": {"b": 0.1, "r": 0.8, "g": 0.1}, "radius": 0.12}],
                            "knit": {"rib_purl": 2, "rib_knit": 2, "pattern": "KNIT_PATTERN_RIB"}})");
  const auto s1 = Settings(R"({"lobes": 3, "spatial_resolution": 16})");
  const auto s2 = Settings(R"({"spatialResolution": 16, "lobes": 3})");
  EXPECT_EQ(FabricKey(a, s1), FabricKey(b, s2));
  EXPECT_EQ(CanonicalFabricJson(a, s1), CanonicalFabricJson(b, s2));
}

TEST(FabricKey, OmittedAndExplicitDefaultsAreTheSameFabric) {
  const auto implicit = Fabric(R"({"knit": {}})");
  const auto explicit_defaults = WithDefaults(implicit);
  EXPECT_EQ(FabricKey(implicit, {}), FabricKey(explicit_defaults, WithDefaults(v1::PrecomputeSettings())));
  EXPECT_EQ(FabricKey(implicit, {}), FabricKey(implicit, Settings(R"({"lookup_table": true, "lobes": 2})")));
}

TEST(FabricKey, NamesAreNotPartOfTheKey) {
  EXPECT_EQ(FabricKey(Fabric(R"({"name": "a", "knit": {}, "yarns": [{"name": "wool"}]})"), {}),
            FabricKey(Fabric(R"({"name": "b", "knit": {}, "yarns": [{"name": "cotton"}]})"), {}));
}

TEST(FabricKey, PinsTheCanonicalForm) {
  // Changing the canonical form silently would orphan every cached fabric: if this
  // value changes on purpose, bump kAssetFormatVersion.
  EXPECT_EQ(FabricKey(Fabric(R"({"knit": {}})"), {}), "d22197a19280f182ddc4c30aef6fbb341abc809bb3749c6a6e4f04977cd4e02e");
}

// Moves one scalar field away from its current value.
void Perturb(Message* message, const FieldDescriptor* field) {
  const Reflection* r = message->GetReflection();
  switch (field->cpp_type()) {
    case FieldDescriptor::CPPTYPE_UINT32: r->SetUInt32(message, field, r->GetUInt32(*message, field) + 1); break;
    case FieldDescriptor::CPPTYPE_UINT64: r->SetUInt64(message, field, r->GetUInt64(*message, field) + 1); break;
    case FieldDescriptor::CPPTYPE_INT32: r->SetInt32(message, field, r->GetInt32(*message, field) + 1); break;
    case FieldDescriptor::CPPTYPE_FLOAT: r->SetFloat(message, field, r->GetFloat(*message, field) + 0.125f); break;
    case FieldDescriptor::CPPTYPE_BOOL: r->SetBool(message, field, !r->GetBool(*message, field)); break;
    case FieldDescriptor::CPPTYPE_ENUM: {
      const auto* type = field->enum_type();
      const int current = r->GetEnumValue(*message, field);
      r->SetEnumValue(message, field, type->value((type->FindValueByNumber(current)->index() + 1) % type->value_count())->number());
      break;
    }
    default: FAIL() << "unhandled field type " << field->full_name();
  }
}

// Calls `check(label, mutate)` once per scalar field reachable from `root`.
void ForEachScalarField(Message* root, const std::string& path,
                        const std::function<void(const std::string&, const std::function<void(Message*)>&)>& check,
                        const std::function<Message*(Message*)>& locate) {
  const auto* descriptor = locate(root)->GetDescriptor();
  for (int i = 0; i < descriptor->field_count(); ++i) {
    const FieldDescriptor* field = descriptor->field(i);
    if (field->name() == "name") continue;  // cosmetic, excluded on purpose
    const std::string field_path = path + "." + field->name();
    if (field->is_repeated()) {
      if (field->cpp_type() == FieldDescriptor::CPPTYPE_MESSAGE) {
        ForEachScalarField(root, field_path + "[0]", check, [=](Message* m) {
          Message* parent = locate(m);
          return parent->GetReflection()->MutableRepeatedMessage(parent, field, 0);
        });
      } else {
        check(field_path, [=](Message* m) {
          Message* parent = locate(m);
          parent->GetReflection()->AddUInt32(parent, field, 1);
        });
      }
    } else if (field->cpp_type() == FieldDescriptor::CPPTYPE_MESSAGE) {
      ForEachScalarField(root, field_path, check, [=](Message* m) {
        Message* parent = locate(m);
        return parent->GetReflection()->MutableMessage(parent, field);
      });
    } else {
      check(field_path, [=](Message* m) { Perturb(locate(m), field); });
    }
  }
}

TEST(FabricKey, ChangesWhenAnySettingChanges) {
  const v1::PrecomputeSettings settings = WithDefaults(v1::PrecomputeSettings());
  const v1::FabricSpec knit = WithDefaults(Fabric(R"({"knit": {}, "yarns": [{}]})"));
  const std::string base = FabricKey(knit, settings);
  int checked = 0;

  v1::PrecomputeSettings settings_root = settings;
  ForEachScalarField(&settings_root, "precompute", [&](const std::string& label, const std::function<void(Message*)>& mutate) {
    // The factored and neural methods' settings do not reach svbrdf's asset, nor its
    // key (tests/core/methods/factored_test.cpp and neural_test.cpp check that they
    // reach their own method's).
    if (label.starts_with("precompute.factored.") || label.starts_with("precompute.neural.")) return;
    v1::PrecomputeSettings changed = settings;
    mutate(&changed);
    EXPECT_NE(FabricKey(knit, changed), base) << label;
    ++checked;
  }, [](Message* m) { return m; });

  for (const char* structure : {R"({"knit": {}, "yarns": [{}]})", R"({"woven": {}, "yarns": [{}]})"}) {
    const v1::FabricSpec fabric = WithDefaults(Fabric(structure));
    const std::string fabric_base = FabricKey(fabric, settings);
    v1::FabricSpec fabric_root = fabric;
    ForEachScalarField(&fabric_root, "fabric", [&](const std::string& label, const std::function<void(Message*)>& mutate) {
      // Its next value, Kajiya-Kay, is what unset means: YarnShadingIsPartOfTheKey.
      if (label.ends_with(".shading")) return;
      v1::FabricSpec changed = fabric;
      mutate(&changed);
      // Setting the other structure of the oneof replaces this one: also a change.
      EXPECT_NE(FabricKey(changed, settings), fabric_base) << label;
      ++checked;
    }, [](Message* m) { return m; });
  }
  EXPECT_GT(checked, 40);
}

TEST(FabricKey, YarnShadingIsPartOfTheKeyAndKajiyaKayIsUnset) {
  const std::string unset = FabricKey(Fabric(R"({"woven": {}})"), {});
  EXPECT_EQ(FabricKey(Fabric(R"({"woven": {}, "yarns": [{"shading": "YARN_SHADING_KAJIYA_KAY"}]})"), {}), unset);
  const std::string microflake = FabricKey(Fabric(R"({"woven": {}, "yarns": [{"shading": "YARN_SHADING_MICROFLAKE"}]})"), {});
  EXPECT_NE(microflake, unset);
  EXPECT_EQ(FabricKey(Fabric(R"({"woven": {}, "yarns": [{"shading": "YARN_SHADING_MICROFLAKE", "height_scale": 1,
                                  "lambert_blend": 1, "diffuse_transmission": 0}]})"), {}), microflake);  // the defaults
  for (const char* changed : {R"("height_scale": 0.5)", R"("lambert_blend": 0.5)", R"("roughness": 0.2)",
                              R"("diffuse_transmission": 0.5)"}) {
    const std::string json =
        std::string(R"({"woven": {}, "yarns": [{"shading": "YARN_SHADING_MICROFLAKE", )") + changed + "}]}";
    EXPECT_NE(FabricKey(Fabric(json.c_str()), {}), microflake) << changed;
  }
}

// With colour components the asset holds no colour (core/methods/colour_sheets.h):
// fabrics that differ only in their yarns' albedos share one key, and only then.
TEST(FabricKey, ColourComponentsLeaveTheAlbedosOut) {
  const auto fabric = [](const char* diffuse, const char* specular) {
    return Fabric((std::string(R"({"woven": {}, "yarns": [{"diffuse_albedo": )") + diffuse +
                   R"(, "specular_albedo": )" + specular + R"(}, {}]})")
                      .c_str());
  };
  const auto red = fabric(R"({"r": 0.8, "g": 0.1, "b": 0.1})", R"({"r": 0.1, "g": 0.1, "b": 0.1})");
  const auto blue = fabric(R"({"r": 0.1, "g": 0.1, "b": 0.8})", R"({"r": 0.02, "g": 0.02, "b": 0.05})");
  const auto components = Settings(R"({"colour_components": true, "indirect_bounces": 0})");
  const auto direct = Settings(R"({"indirect_bounces": 0})");
  EXPECT_EQ(FabricKey(red, components), FabricKey(blue, components));
  EXPECT_EQ(CanonicalFabricJson(red, components).find("albedo"), std::string::npos);
  EXPECT_NE(FabricKey(red, direct), FabricKey(blue, direct));
  EXPECT_NE(FabricKey(red, components), FabricKey(red, direct));
  // Explicitly false is unset: the keys of fabrics without components stay as they were.
  EXPECT_EQ(FabricKey(red, Settings(R"({"colour_components": false, "indirect_bounces": 0})")),
            FabricKey(red, direct));
  // Everything but the albedos still counts.
  auto rougher = blue;
  rougher.mutable_yarns(0)->set_roughness(0.2f);
  EXPECT_NE(FabricKey(rougher, components), FabricKey(red, components));
}

TEST(FabricKey, AssetFormatVersionIsPartOfTheCanonicalForm) {
  EXPECT_NE(CanonicalFabricJson(Fabric(R"({"knit": {}})"), {}).find("\"asset_format_version\":" +
                                                                     std::to_string(kAssetFormatVersion)),
            std::string::npos);
}

// A yarn volume's light model keys its fabrics, and only those: tube knits and weaves keep
// their keys when the model changes.
TEST(FabricKey, TheVolumesLightModelKeysFabricsWithAYarnVolumeOnly) {
  const std::string model = "\"volume_light_model\":" + std::to_string(kVolumeLightModelVersion);
  for (const char* volume : {R"({"knit": {}, "yarns": [{"plies": 2}]})", R"({"knit": {}, "yarns": [{"fuzz": 0.2}]})"}) {
    EXPECT_NE(CanonicalFabricJson(Fabric(volume), {}).find(model), std::string::npos) << volume;
  }
  EXPECT_EQ(CanonicalFabricJson(Fabric(R"({"knit": {}})"), {}).find("volume_light_model"), std::string::npos);
  EXPECT_EQ(CanonicalFabricJson(Fabric(R"({"woven": {}})"), {}).find("volume_light_model"), std::string::npos);
}

}  // namespace
}  // namespace loom
