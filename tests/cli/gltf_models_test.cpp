// `ssgi render` on every glTF 2.0 file of Debian's assimp-testmodels (/usr/share/assimp/models/glTF2,
// installed by setup.sh): each supported one renders, each unsupported one is refused with one line
// and leaves no output, as docs/user-guide.md "glTF files" lists them.
#include <catch2/catch.hpp>
#include <filesystem>
#include <string>
#include <vector>

#include "core/scene.h"
#include "passes/frame/frame.h"
#include "tests/passes/test_scenes.h"
#include "tests/test_support.h"

namespace ssgi {
namespace {

namespace fs = std::filesystem;

const fs::path kModels = "/usr/share/assimp/models/glTF2";

// Files that render, relative to kModels.
const std::vector<std::string> kRendered = {
    "2CylinderEngine-glTF-Binary/2CylinderEngine.glb",
    "BoxBadNormals-glTF-Binary/BoxBadNormals.glb",
    "BoxTexcoords-glTF/boxTexcoords.gltf",
    "BoxTextured-glTF/BoxTextured.gltf",
    "BoxTextured-glTF-Binary/BoxTextured.glb",
    "BoxTextured-glTF-Embedded/BoxTextured.gltf",
    "BoxTextured-glTF-pbrSpecularGlossiness/BoxTextured.gltf",
    "ClearCoat-glTF/ClearCoatTest.gltf",
    "cameras/Cameras.gltf",
    "glTF-Asset-Generator/Mesh_PrimitiveMode/Mesh_PrimitiveMode_04.gltf",
    "glTF-Asset-Generator/Mesh_PrimitiveMode/Mesh_PrimitiveMode_05.gltf",
    "glTF-Asset-Generator/Mesh_PrimitiveMode/Mesh_PrimitiveMode_06.gltf",
    "glTF-Asset-Generator/Mesh_PrimitiveMode/Mesh_PrimitiveMode_11.gltf",
    "glTF-Asset-Generator/Mesh_PrimitiveMode/Mesh_PrimitiveMode_12.gltf",
    "glTF-Asset-Generator/Mesh_PrimitiveMode/Mesh_PrimitiveMode_13.gltf",
    "glTF-Asset-Generator/Mesh_PrimitiveMode/Mesh_PrimitiveMode_14.gltf",
    "glTF-Asset-Generator/Mesh_PrimitiveMode/Mesh_PrimitiveMode_15.gltf",
    "glTF-Sample-Models/AnimatedMorphCube-glTF/AnimatedMorphCube.gltf",
    "simple_skin/simple_skin.gltf",
    "textureTransform/TextureTransformTest.gltf",
    "wrongTypes/badExtension.gltf",
    "wrongTypes/badNumber.gltf",
    "wrongTypes/badObject.gltf",
    "wrongTypes/badString.gltf",
    "wrongTypes/badUint.gltf",
};

// Files that are refused, with a word of the one line that says why.
const std::vector<std::pair<std::string, std::string>> kRefused = {
    {"BoxTextured-glTF-techniqueWebGL/BoxTextured.gltf", "KHR_technique_webgl"},
    {"BoxWithInfinites-glTF-Binary/BoxWithInfinites.glb", "non-finite"},
    {"IncorrectVertexArrays/Cube.gltf", "points or lines"},
    {"IndexOutOfRange/AllIndicesOutOfRange.gltf", "beyond the"},
    {"IndexOutOfRange/IndexOutOfRange.gltf", "beyond the"},
    {"MissingBin/BoxTextured.gltf", "BoxTextured0.bin"},
    {"RecursiveNodes/RecursiveNodes.gltf", "cycle"},
    {"SchemaFailures/sceneWrongType.gltf", "BoxTextured0.bin"},
    {"TestNoRootNode/NoScene.gltf", "no triangles"},
    {"TestNoRootNode/SceneWithoutNodes.gltf", "no triangles"},
    {"draco/2CylinderEngine.gltf", "Draco"},
    {"glTF-Asset-Generator/Mesh_PrimitiveMode/Mesh_PrimitiveMode_00.gltf", "points or lines"},
    {"glTF-Asset-Generator/Mesh_PrimitiveMode/Mesh_PrimitiveMode_01.gltf", "points or lines"},
    {"glTF-Asset-Generator/Mesh_PrimitiveMode/Mesh_PrimitiveMode_02.gltf", "points or lines"},
    {"glTF-Asset-Generator/Mesh_PrimitiveMode/Mesh_PrimitiveMode_03.gltf", "points or lines"},
    {"glTF-Asset-Generator/Mesh_PrimitiveMode/Mesh_PrimitiveMode_07.gltf", "points or lines"},
    {"glTF-Asset-Generator/Mesh_PrimitiveMode/Mesh_PrimitiveMode_08.gltf", "points or lines"},
    {"glTF-Asset-Generator/Mesh_PrimitiveMode/Mesh_PrimitiveMode_09.gltf", "points or lines"},
    {"glTF-Asset-Generator/Mesh_PrimitiveMode/Mesh_PrimitiveMode_10.gltf", "points or lines"},
    {"issue_3269/texcoord_crash.gltf", "TEXCOORD_0"},
    {"wrongTypes/badArray.gltf", "no triangles"},
};

size_t Lines(const std::string& text, const std::string& prefix) {
  size_t count = 0;
  for (size_t at = text.find(prefix); at != std::string::npos; at = text.find(prefix, at + 1)) ++count;
  return count;
}

TEST_CASE("render: every glTF 2.0 file of assimp-testmodels renders or is refused with one line", "[cli][gltf]") {
  INFO("assimp-testmodels is missing: ./setup.sh installs it");
  REQUIRE(fs::is_directory(kModels));
  // Every .gltf and .glb there is in one of the two lists.
  size_t listed = 0;
  for (const fs::directory_entry& entry : fs::recursive_directory_iterator(kModels)) {
    const std::string ext = entry.path().extension().string();
    if (ext != ".gltf" && ext != ".glb") continue;
    const std::string name = fs::relative(entry.path(), kModels).string();
    CAPTURE(name);
    const bool rendered = std::find(kRendered.begin(), kRendered.end(), name) != kRendered.end();
    const bool refused = std::any_of(kRefused.begin(), kRefused.end(), [&](const auto& r) { return r.first == name; });
    CHECK(rendered != refused);
    ++listed;
  }
  CHECK(listed == kRendered.size() + kRefused.size());

  // In process (a run of the executable costs half a second to start): each loads and renders.
  for (const std::string& name : kRendered) {
    CAPTURE(name);
    std::string problem;
    try {
      const SceneFile file = LoadSceneFile(kModels / name);
      const Frame frame = RenderFrame(file.scene, test::ConfigOf(test::Sized(file.scene, 48, 36)));
      CHECK(frame.Result().c[0].xsize() == 48);
    } catch (const std::exception& e) {
      problem = e.what();
    }
    CHECK(problem == "");
  }
  for (const auto& [name, why] : kRefused) {
    CAPTURE(name);
    const std::string message = test::InputErrorOf([&] { LoadSceneFile(kModels / name); });
    CHECK(message.find('\n') == std::string::npos);
    CHECK_THAT(message, Catch::Contains(name) && Catch::Contains(why));
  }
  // Through the command line: a refusal is one line, exit 1, no output; a model renders.
  test::ScratchDir dir("gltf-models");
  for (const std::string name : {"draco/2CylinderEngine.gltf", "MissingBin/BoxTextured.gltf"}) {
    CAPTURE(name);
    const test::CommandResult r = test::RunProgram(
        test::CliPath(), "render " + test::Quote(kModels / name) + " -o " + test::Quote(dir / "out.png"));
    CHECK(r.exitCode == 1);
    CHECK(Lines(r.output, "ssgi: error: ") == 1);
    CHECK(Lines(r.output, "\n") == 1);
    CHECK_FALSE(fs::exists(dir / "out.png"));
  }
}

TEST_CASE("render: a glTF model gives the same bytes at 1, 2 and 3 threads", "[cli][gltf][determinism]") {
  test::ScratchDir dir("gltf-threads");
  const fs::path model = kModels / "2CylinderEngine-glTF-Binary/2CylinderEngine.glb";
  REQUIRE(fs::exists(model));
  std::vector<test::StoredImage> images;
  for (const int threads : {1, 2, 3}) {
    const fs::path out = dir / ("t" + std::to_string(threads) + ".png");
    const test::CommandResult r =
        test::RunProgram(test::CliPath(), "render " + test::Quote(model) + " -o " + test::Quote(out) +
                                              " --size 131x97 --threads " + std::to_string(threads));
    REQUIRE(r.exitCode == 0);
    images.push_back(test::ReadStoredImage(out));
  }
  CHECK(images[0].bytes == images[1].bytes);
  CHECK(images[0].bytes == images[2].bytes);
}

}  // namespace
}  // namespace ssgi
