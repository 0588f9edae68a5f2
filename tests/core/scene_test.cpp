#include "core/scene.h"

#include <catch2/catch.hpp>
#include <cmath>
#include <string>

#include "core/error.h"
#include "tests/test_support.h"

namespace ssgi {
namespace {

namespace fs = std::filesystem;

// The message of the InputError that loading `file` throws ("" when none is thrown).
std::string LoadError(const fs::path& file) {
  return test::InputErrorOf([&] { LoadScene(file); });
}

// A unit right triangle in the z = 0 plane facing +z, with material "paint" (textured) and "bare".
void WriteTriangleObj(const test::ScratchDir& dir) {
  test::WriteText(dir / "tri.mtl", "newmtl paint\nKd 0.5 0.5 0.5\nPr 0.4\nmap_Kd albedo.ppm\nnewmtl bare\nKd 1 0 0\n");
  test::WriteText(dir / "albedo.ppm", "P3\n1 1\n255\n10 20 30\n");
  test::WriteText(dir / "tri.obj",
                  "mtllib tri.mtl\nv 0 0 0\nv 1 0 0\nv 0 1 0\nvt 0 0\nvt 1 0\nvt 0 1\n"
                  "usemtl paint\nf 1/1 2/2 3/3\nusemtl bare\nf 1/1 3/3 2/2\n");
}

fs::path WriteScene(const test::ScratchDir& dir, const std::string& json) {
  test::WriteText(dir / "scene.json", json);
  return dir / "scene.json";
}

bool Finite(const glm::vec3& v) { return std::isfinite(v.x) && std::isfinite(v.y) && std::isfinite(v.z); }

TEST_CASE("a bare OBJ gets a framing camera, the default light and default settings", "[scene]") {
  test::ScratchDir dir("scene-bare");
  WriteTriangleObj(dir);
  const Scene scene = LoadScene(dir / "tri.obj");
  CHECK(scene.source == dir / "tri.obj");
  CHECK(scene.mesh.TriangleCount() == 2);
  CHECK(scene.materials.size() == 2);
  CHECK(scene.textures.size() == 1);
  CHECK(scene.materials[0].baseColorTexture == 0);
  CHECK(scene.materials[1].baseColorTexture == kNoTexture);
  REQUIRE(scene.directionalLights.size() == 1);
  CHECK(scene.directionalLights[0].direction == DefaultLight().direction);
  CHECK(scene.spotLights.empty());
  CHECK(LoadSceneFile(dir / "tri.obj").render.empty());
  const CameraDesc framed = FrameMesh(scene.mesh, 1024, 1024);
  CHECK(scene.camera.position == framed.position);
  CHECK(scene.camera.target == framed.target);
}

TEST_CASE("a JSON scene reads every section", "[scene]") {
  test::ScratchDir dir("scene-json");
  WriteTriangleObj(dir);
  const SceneFile file = LoadSceneFile(WriteScene(dir, R"({
    "camera": { "position": [4, 3, 6], "target": [0, 0.5, 0], "fov_y_deg": 30, "near": 0.1 },
    "lights": [
      { "type": "directional", "direction": [0, -2, 0], "irradiance": [3, 2.9, 2.7], "cast_shadows": false },
      { "type": "spot", "position": [0, 4, 0], "direction": [0, -1, 0], "inner_cone_deg": 10,
        "outer_cone_deg": 25, "radius": 0.1, "intensity": [40, 40, 40] }
    ],
    "objects": [
      { "obj": "tri.obj" },
      { "obj": "tri.obj", "transform": { "translate": [1, 2, 3], "rotate_deg": [0, 90, 0], "scale": 2 },
        "materials": { "*": { "roughness": 0.9, "metallic": 1 }, "bare": { "roughness": 0.1, "two_sided": true } } }
    ],
    "render": { "width": 320, "height": 200, "exposure_ev": -1.5, "tonemap": "clamp", "background": [0.1, 0.2, 0.3],
                "normal_encoding": "xyz8", "effects": { "shadows": false, "reflections": "on" } }
  })"));

  const Scene& scene = file.scene;
  CHECK(scene.camera.position == glm::vec3(4, 3, 6));
  CHECK(scene.camera.up == glm::vec3(0, 1, 0));
  CHECK(scene.camera.fovYDegrees == 30.0f);
  CHECK(scene.camera.nearPlane == 0.1f);

  REQUIRE(scene.directionalLights.size() == 1);
  CHECK(scene.directionalLights[0].direction == glm::vec3(0, -1, 0));
  CHECK(scene.directionalLights[0].irradiance == glm::vec3(3.0f, 2.9f, 2.7f));
  CHECK(scene.directionalLights[0].angularDiameterDegrees == 0.53f);
  CHECK_FALSE(scene.directionalLights[0].castShadows);
  REQUIRE(scene.spotLights.size() == 1);
  CHECK(scene.spotLights[0].outerConeDegrees == 25.0f);
  CHECK(scene.spotLights[0].radius == 0.1f);
  CHECK(scene.spotLights[0].castShadows);

  // The render block as written, nested keys dotted, for the frame configuration to interpret.
  std::vector<std::string> render;
  for (const RenderBlockEntry& e : file.render) render.push_back(e.key + "=" + e.json + "@" + std::to_string(e.line));
  CHECK(render == std::vector<std::string>{"background=[0.1,0.2,0.3]@13", "effects.reflections=\"on\"@14",
                                           "effects.shadows=false@14", "exposure_ev=-1.5@13", "height=200@13",
                                           "normal_encoding=\"xyz8\"@14", "tonemap=\"clamp\"@13", "width=320@13"});

  // The OBJ is loaded once; each object has its own materials; the texture is loaded once.
  CHECK(scene.mesh.TriangleCount() == 4);
  REQUIRE(scene.materials.size() == 4);
  CHECK(scene.textures.size() == 1);
  CHECK(scene.materials[0].roughness == 0.4f);
  CHECK(scene.materials[2].roughness == 0.9f);  // "*"
  CHECK(scene.materials[2].metallic == 1.0f);
  CHECK(scene.materials[3].roughness == 0.1f);  // "*" then "bare"
  CHECK(scene.materials[3].metallic == 1.0f);
  CHECK(scene.materials[3].twoSided);
  CHECK_FALSE(scene.materials[2].twoSided);
  CHECK(scene.materials[2].baseColorTexture == scene.materials[0].baseColorTexture);
  CHECK(scene.mesh.materials == std::vector<uint32_t>{0, 1, 2, 3});

  // Second copy: x -> -z after the 90 degree turn about y, scaled by 2, moved by (1, 2, 3).
  const size_t second = scene.mesh.positions.size() / 2;
  CHECK(scene.mesh.positions[second + 1].x == Approx(1.0f));
  CHECK(scene.mesh.positions[second + 1].y == Approx(2.0f));
  CHECK(scene.mesh.positions[second + 1].z == Approx(1.0f));
  CHECK(scene.mesh.normals[second].x == Approx(1.0f));  // +z turned to +x
}

TEST_CASE("transforms keep normals perpendicular and mirrored faces counter-clockwise", "[scene]") {
  test::ScratchDir dir("scene-transform");
  WriteTriangleObj(dir);
  const SceneFile file = LoadSceneFile(WriteScene(dir, R"({ "objects": [ { "obj": "tri.obj",
      "transform": { "scale": [-1, 3, 0.5], "rotate_deg": [30, 0, 0] } } ] })"));
  const Mesh& mesh = file.scene.mesh;
  for (size_t t = 0; t < mesh.TriangleCount(); ++t) {
    const glm::vec3 a = mesh.positions[mesh.indices[3 * t]];
    const glm::vec3 b = mesh.positions[mesh.indices[3 * t + 1]];
    const glm::vec3 c = mesh.positions[mesh.indices[3 * t + 2]];
    const glm::vec3 face = glm::normalize(glm::cross(b - a, c - a));
    for (int k = 0; k < 3; ++k) {
      const glm::vec3 n = mesh.normals[mesh.indices[3 * t + k]];
      CHECK(std::abs(glm::length(n) - 1.0f) < 1e-5f);
      CHECK(glm::dot(n, face) > 0.9999f);  // same side as the (re-wound) geometric normal
    }
  }
}

TEST_CASE("lights: omitted gives the default light, an empty array none", "[scene]") {
  test::ScratchDir dir("scene-lights");
  WriteTriangleObj(dir);
  const Scene none = LoadScene(WriteScene(dir, R"({ "lights": [], "objects": [ { "obj": "tri.obj" } ] })"));
  CHECK(none.directionalLights.empty());
  CHECK(none.spotLights.empty());
  const Scene fallback = LoadScene(WriteScene(dir, R"({ "objects": [ { "obj": "tri.obj" } ] })"));
  REQUIRE(fallback.directionalLights.size() == 1);
  CHECK(fallback.directionalLights[0].angularDiameterDegrees == DefaultLight().angularDiameterDegrees);
}

TEST_CASE("FrameMesh frames the bounding sphere and survives degenerate meshes", "[scene]") {
  Mesh mesh;
  mesh.positions = {{-1, 0, 0}, {1, 0, 0}, {0, -1, 0}, {0, 1, 0}, {0, 0, -1}, {0, 0, 1}};
  const CameraDesc camera = FrameMesh(mesh, 100, 100);
  const float distance = 1.0f / std::sin(glm::radians(20.0f)) * 1.15f;
  CHECK(glm::length(camera.position) == Approx(distance));
  CHECK(glm::normalize(camera.position).x == Approx(glm::normalize(glm::vec3(0.6f, 0.45f, 1.0f)).x));
  CHECK(camera.target == glm::vec3(0.0f));
  CHECK(camera.fovYDegrees == 40.0f);
  CHECK(camera.nearPlane == Approx((distance - 1.0f) * 0.02f));
  // A portrait image fits the sphere in its narrower horizontal field of view: further away.
  CHECK(glm::length(FrameMesh(mesh, 50, 100).position) > distance * 1.5f);

  Mesh point;
  point.positions = {{2, 3, 4}};
  Mesh empty;
  for (const Mesh* m : {&point, &empty}) {
    const CameraDesc c = FrameMesh(*m, 64, 48);
    CHECK(Finite(c.position));
    CHECK(Finite(c.target));
    CHECK(c.nearPlane > 0.0f);
    CHECK(c.position != c.target);
  }
}

TEST_CASE("DefaultLight comes from the upper left with a 2 degree sun", "[scene]") {
  const DirectionalLight light = DefaultLight();
  CHECK(light.direction.x == Approx(glm::normalize(glm::vec3(-0.5f, -1.0f, -0.35f)).x));
  CHECK(light.direction.y < 0.0f);
  CHECK(glm::length(light.direction) == Approx(1.0f));
  CHECK(light.irradiance == glm::vec3(3.0f));
  CHECK(light.angularDiameterDegrees == 2.0f);
}

TEST_CASE("Sponza loads as a bare OBJ with its textures", "[scene][sponza]") {
  const fs::path file = test::ThirdPartyScenesDir() / "dabrovic-sponza" / "sponza.obj";
  if (!fs::exists(file)) {
    WARN(test::MissingScenesMessage(file));
    return;
  }
  const Scene scene = LoadScene(file);
  CHECK(scene.mesh.TriangleCount() == 66450);
  REQUIRE(scene.materials.size() == 20);
  int textured = 0;
  for (const Material& m : scene.materials) textured += m.baseColorTexture != kNoTexture;
  CHECK(textured == 19);               // all but sp_01_stub_baza_, which has no map_Kd
  CHECK(scene.textures.size() == 12);  // distinct map_Kd images
  for (const Texture& t : scene.textures) CHECK(t.levels.back().width == 1);
}

TEST_CASE("bad scenes throw InputError naming the file, line and key", "[scene][errors]") {
  test::ScratchDir dir("scene-errors");
  WriteTriangleObj(dir);
  auto errorFor = [&](const std::string& json) { return LoadError(WriteScene(dir, json)); };
  const std::string objects = R"("objects": [ { "obj": "tri.obj" } ])";

  // Syntax error on line 3: the missing comma.
  CHECK_THAT(errorFor("{\n  \"objects\": [ { \"obj\": \"tri.obj\" } ]\n  \"render\": {}\n}"),
             Catch::Contains("scene.json:3:"));
  CHECK_THAT(errorFor("{\n  " + objects +
                      ",\n  \"camera\": { \"position\": [1, 2, 3], \"target\": [0, 0, 0],\n"
                      "    \"fov_y_deg\": 200 }\n}"),
             Catch::Contains("scene.json:4: camera.fov_y_deg must be in (0, 180), got 200"));
  CHECK_THAT(errorFor("{ " + objects + R"(, "render": [1] })"), Catch::Contains("render must be an object"));
  CHECK_THAT(
      errorFor("{ " + objects + R"(, "camera": { "position": [1, 2, 3], "target": [0, 0, 0], "fov_y_deg": 0 } })"),
      Catch::Contains("scene.json") && Catch::Contains("camera.fov_y_deg"));
  CHECK_THAT(errorFor("{ " + objects + R"(, "camera": { "position": [0, 2, 0], "target": [0, 0, 0] } })"),
             Catch::Contains("camera.up"));
  CHECK_THAT(errorFor("{ " + objects + R"(, "camera": { "position": [0, 2] , "target": [0, 0, 0] } })"),
             Catch::Contains("camera.position must be an array of 3 numbers"));
  CHECK_THAT(errorFor("{ " + objects + R"(, "lights": [ { "type": "area" } ] })"), Catch::Contains("lights[0].type"));
  CHECK_THAT(errorFor("{ " + objects +
                      R"(, "lights": [ { "type": "spot", "position": [0, 1, 0], "direction": [0, 0, 0] } ] })"),
             Catch::Contains("lights[0].direction must not be zero"));
  CHECK_THAT(
      errorFor("{ " + objects + R"(, "lights": [ { "type": "spot", "position": [0, 1, 0], "direction": [0, -1, 0],
                      "inner_cone_deg": 40, "outer_cone_deg": 30 } ] })"),
      Catch::Contains("inner_cone_deg"));
  CHECK_THAT(errorFor(R"({ "objects": [] })"), Catch::Contains("scene.json") && Catch::Contains("objects"));
  CHECK_THAT(errorFor(R"({ "render": {} })"), Catch::Contains("objects is required"));
  CHECK_THAT(errorFor("[1, 2]"), Catch::Contains("scene.json") && Catch::Contains("JSON object"));
  CHECK_THAT(errorFor(R"({ "objects": [ { "obj": "tri.obj" } ], "objects": [] })"),
             Catch::Contains("duplicate key objects"));
  CHECK_THAT(errorFor("{\n\"objects\": [\n { \"obj\": \"missing.obj\" } ] }"),
             Catch::Contains("scene.json:3:") && Catch::Contains("missing.obj"));
  CHECK_THAT(errorFor(R"({ "objects": [ { "obj": "tri.obj", "transform": { "scale": [1, 0, 1] } } ] })"),
             Catch::Contains("objects[0].transform.scale must not be zero"));
  CHECK_THAT(errorFor(R"({ "objects": [ { "obj": "tri.obj", "materials": { "gold": { "metallic": 1 } } } ] })"),
             Catch::Contains("objects[0].materials.gold") && Catch::Contains("tri.obj has no material 'gold'"));
  CHECK_THAT(errorFor(R"({ "objects": [ { "obj": "tri.obj", "materials": { "*": { "metallic": 2 } } } ] })"),
             Catch::Contains("objects[0].materials.*.metallic must be in [0, 1], got 2"));
  CHECK_THAT(errorFor(R"({ "objects": [ { "obj": "tri.obj" } ], "render": { "exposure_ev": 1e999 } })"),
             Catch::Contains("scene.json:1:"));

  // Errors inside the OBJ name the OBJ and its line.
  test::WriteText(dir / "bad.obj", "v 0 0 0\nv nan 0 0\nv 0 1 0\nf 1 2 3\n");
  CHECK_THAT(errorFor(R"({ "objects": [ { "obj": "bad.obj" } ] })"), Catch::Contains("bad.obj:2:"));
  CHECK_THAT(LoadError(dir / "bad.obj"), Catch::Contains("bad.obj:2:"));

  CHECK_THAT(LoadError(dir / "absent.json"), Catch::Contains("absent.json"));
  test::WriteText(dir / "scene.yaml", "objects: []");
  CHECK_THAT(LoadError(dir / "scene.yaml"), Catch::Contains("scene.yaml"));
}

}  // namespace
}  // namespace ssgi
