#include "core/gl/shader_program.h"

#include <gtest/gtest.h>

#include "core/gl/egl_context.h"
#include "core/gl/shader_sources.h"
#include "core/util/error.h"

namespace loom::gl {
namespace {

TEST(ShaderProgram, CompileErrorNamesTheFileAndLine) {
  const auto context = EglContext::Create();
  const std::string broken = "#version 450 core\nvoid main() {\n  gl_Position = vec4(1.0);\n  undefined_name = 2;\n}\n";
  try {
    ShaderProgram::Link({{GL_VERTEX_SHADER, "broken.vert", broken}});
    FAIL() << "a shader with an undefined name compiled";
  } catch (const Error& error) {
    const std::string message = error.what();
    EXPECT_NE(message.find("shader broken.vert failed to compile"), std::string::npos) << message;
    EXPECT_NE(message.find("broken.vert:4:"), std::string::npos) << message;
    EXPECT_NE(message.find("undefined_name"), std::string::npos) << message;
  }
}

TEST(ShaderProgram, LinkErrorNamesTheStages) {
  const auto context = EglContext::Create();
  // The fragment shader reads an input the vertex shader never writes with that type.
  const std::string vertex = "#version 450 core\nout vec2 v_value;\nvoid main() { v_value = vec2(0); gl_Position = vec4(0); }\n";
  const std::string fragment = "#version 450 core\nin vec4 v_value;\nout vec4 o;\nvoid main() { o = v_value; }\n";
  try {
    ShaderProgram::Link({{GL_VERTEX_SHADER, "a.vert", vertex}, {GL_FRAGMENT_SHADER, "b.frag", fragment}});
    FAIL() << "mismatched interfaces linked";
  } catch (const Error& error) {
    EXPECT_NE(std::string(error.what()).find("a.vert + b.frag failed to link"), std::string::npos) << error.what();
  }
}

TEST(ShaderProgram, AnnotatesMesaAndNvidiaLogLines) {
  const std::vector<std::string> files = {"s.frag", "lib.glsl"};
  EXPECT_EQ(AnnotateShaderLog("0:12(5): error: `x' undeclared\n", files), "s.frag:12: error: `x' undeclared\n");
  EXPECT_EQ(AnnotateShaderLog("1:3(5): error: `y' undeclared\n", files), "lib.glsl:3: error: `y' undeclared\n");
  EXPECT_EQ(AnnotateShaderLog("0(7) : error C1008: undefined variable \"x\"\n", files),
            "s.frag:7: error C1008: undefined variable \"x\"\n");
  EXPECT_EQ(AnnotateShaderLog("something else\n", files), "s.frag: something else\n");
}

TEST(ShaderProgram, ErrorsAfterAnIncludeKeepTheStagesOwnLineNumbers) {
  const auto context = EglContext::Create();
  const std::string text =
      "#version 450 core\n#include \"hemisphere_map.glsl\"\nout vec4 o;\nvoid main() {\n  o = vec4(nope);\n}\n";
  const ExpandedSource expanded = ExpandIncludes("with_include.frag", text);
  // hemisphere_map.glsl includes constants.glsl: nested files get their own numbers.
  ASSERT_EQ(expanded.files,
            (std::vector<std::string>{"with_include.frag", "hemisphere_map.glsl", "constants.glsl"}));
  try {
    ShaderProgram::Link({{GL_FRAGMENT_SHADER, "with_include.frag", text}});
    FAIL() << "an undefined name compiled";
  } catch (const Error& error) {
    EXPECT_NE(std::string(error.what()).find("with_include.frag:5:"), std::string::npos) << error.what();
  }
}

TEST(ShaderProgram, AnIncludedFileIsExpandedOnce) {
  const std::string text = "#version 450 core\n#include \"hemisphere_map.glsl\"\n#include \"hemisphere_map.glsl\"\n";
  const ExpandedSource expanded = ExpandIncludes("twice.frag", text);
  size_t count = 0;
  for (size_t at = 0; (at = expanded.text.find("vec2 ConcentricSquareToDisk", at)) != std::string::npos; ++at) ++count;
  EXPECT_EQ(count, 1u);
}

TEST(ShaderProgram, EveryEmbeddedShaderCompiles) {
  const auto context = EglContext::Create();
  ASSERT_FALSE(EmbeddedShaders().empty());
  for (const ShaderSource& source : EmbeddedShaders()) {
    const std::string name(source.name);
    if (!name.ends_with(".vert") && !name.ends_with(".frag")) continue;  // included snippets
    const GLenum type = name.ends_with(".vert") ? GL_VERTEX_SHADER : GL_FRAGMENT_SHADER;
    EXPECT_NO_THROW(ShaderProgram::Link({{type, name, std::string(source.text)}})) << name;
  }
}

}  // namespace
}  // namespace loom::gl
