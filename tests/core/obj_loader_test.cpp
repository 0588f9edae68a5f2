#include "core/obj_loader.h"

#include <catch2/catch.hpp>
#include <cmath>
#include <set>
#include <string>

#include "core/error.h"
#include "tests/test_support.h"

namespace ssgi {
namespace {

namespace fs = std::filesystem;

// The message of the InputError that loading `file` throws ("" when none is thrown).
std::string LoadError(const fs::path& file) {
  return test::InputErrorOf([&] { LoadObjModel(file); });
}

glm::vec3 FaceNormal(const Mesh& mesh, size_t triangle) {
  const glm::vec3 a = mesh.positions[mesh.indices[3 * triangle]];
  const glm::vec3 b = mesh.positions[mesh.indices[3 * triangle + 1]];
  const glm::vec3 c = mesh.positions[mesh.indices[3 * triangle + 2]];
  return glm::normalize(glm::cross(b - a, c - a));
}

bool IsUnit(const glm::vec3& n) {
  return std::isfinite(n.x) && std::isfinite(n.y) && std::isfinite(n.z) && std::abs(glm::length(n) - 1.0f) < 1e-5f;
}

constexpr const char* kCube =
    "v -1 -1 -1\nv 1 -1 -1\nv 1 1 -1\nv -1 1 -1\nv -1 -1 1\nv 1 -1 1\nv 1 1 1\nv -1 1 1\n"
    "f 1 4 3 2\nf 5 6 7 8\nf 1 2 6 5\nf 4 8 7 3\nf 1 5 8 4\nf 2 3 7 6\n";

TEST_CASE("quads are triangulated and normals generated", "[obj]") {
  test::ScratchDir dir("obj-quad");
  test::WriteText(dir / "quad.obj",
                  "v 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\nvt 0 0\nvt 1 0\nvt 1 1\nvt 0 1\nf 1/1 2/2 3/3 4/4\n");
  const ObjModel model = LoadObjModel(dir / "quad.obj");
  const Mesh& mesh = model.mesh;
  REQUIRE(mesh.TriangleCount() == 2);
  REQUIRE(mesh.positions.size() == 4);  // the diagonal's corners are shared
  REQUIRE(mesh.normals.size() == 4);
  REQUIRE(mesh.uvs.size() == 4);
  for (const glm::vec3& n : mesh.normals) CHECK(n == glm::vec3(0.0f, 0.0f, 1.0f));
  for (size_t v = 0; v < 4; ++v) CHECK(mesh.uvs[v] == glm::vec2(mesh.positions[v]));
  for (size_t t = 0; t < 2; ++t) CHECK(glm::dot(FaceNormal(mesh, t), glm::vec3(0, 0, 1)) > 0.999f);
  REQUIRE(model.materials.size() == 1);
  CHECK(model.materials[0].material.name == kDefaultMaterialName);
  CHECK(model.materials[0].material.baseColor == glm::vec3(0.8f));
  CHECK(model.materials[0].material.roughness == 0.5f);
  CHECK(mesh.materials == std::vector<uint32_t>{0, 0});
}

TEST_CASE("generated normals keep a cube's edges sharp", "[obj]") {
  test::ScratchDir dir("obj-cube");
  test::WriteText(dir / "cube.obj", kCube);
  const Mesh mesh = LoadObjModel(dir / "cube.obj").mesh;
  REQUIRE(mesh.TriangleCount() == 12);
  CHECK(mesh.positions.size() == 24);  // each corner splits into its three faces
  for (size_t t = 0; t < mesh.TriangleCount(); ++t) {
    const glm::vec3 face = FaceNormal(mesh, t);
    // Outward-facing (counter-clockwise) and every corner's normal equal to its face's.
    CHECK(glm::dot(face, mesh.positions[mesh.indices[3 * t]]) > 0.0f);
    for (int k = 0; k < 3; ++k) CHECK(glm::dot(mesh.normals[mesh.indices[3 * t + k]], face) > 0.99999f);
  }
}

TEST_CASE("generated normals are smooth across gentle bends", "[obj]") {
  test::ScratchDir dir("obj-smooth");
  // A 3x3 height field bent by 20 degrees at most between neighbouring faces.
  std::string text;
  for (int j = 0; j < 3; ++j)
    for (int i = 0; i < 3; ++i)
      text += "v " + std::to_string(i) + " " + std::to_string(j) + " " + (i == 1 ? "0.3" : "0") + "\n";
  text += "f 1 2 5 4\nf 2 3 6 5\nf 4 5 8 7\nf 5 6 9 8\n";
  test::WriteText(dir / "bent.obj", text);
  const Mesh mesh = LoadObjModel(dir / "bent.obj").mesh;
  CHECK(mesh.positions.size() == 9);  // one vertex per position: no crease split
  for (size_t v = 0; v < mesh.positions.size(); ++v) {
    CHECK(IsUnit(mesh.normals[v]));
    // On the ridge: between the normals of the faces either side, (-+0.3, 0, 1) / |.|.
    if (mesh.positions[v].x == 1.0f) CHECK(std::abs(mesh.normals[v].x) < 0.28f);
  }
}

TEST_CASE("zero-area triangles get finite normals", "[obj]") {
  test::ScratchDir dir("obj-degenerate");
  // A proper triangle, a collinear one sharing its corners and a fully collapsed one.
  test::WriteText(dir / "mixed.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\nv 2 0 0\nf 1 2 3\nf 1 2 4\nf 3 3 3\n");
  const ObjModel mixed = LoadObjModel(dir / "mixed.obj");
  REQUIRE(mixed.mesh.TriangleCount() == 3);  // kept: the rasterizer drops them
  for (const glm::vec3& n : mixed.mesh.normals) CHECK(IsUnit(n));

  test::WriteText(dir / "only.obj", "v 1 1 1\nv 1 1 1\nv 1 1 1\nf 1 2 3\n");
  const ObjModel only = LoadObjModel(dir / "only.obj");
  for (const glm::vec3& n : only.mesh.normals) CHECK(IsUnit(n));
}

TEST_CASE("supplied normals are normalized, and zero ones are generated", "[obj]") {
  test::ScratchDir dir("obj-normals");
  test::WriteText(dir / "n.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\nvn 0 0 2\nvn 0 0 0\nf 1//1 2//1 3//2\n");
  const Mesh mesh = LoadObjModel(dir / "n.obj").mesh;
  REQUIRE(mesh.positions.size() == 3);
  for (const glm::vec3& n : mesh.normals) CHECK(n == glm::vec3(0.0f, 0.0f, 1.0f));
}

TEST_CASE("materials map from MTL values and textures", "[obj]") {
  test::ScratchDir dir("obj-materials");
  fs::create_directories(dir / "tex");
  for (const char* name : {"tex/albedo.png", "rough.png", "metal.png", "mask.png"}) test::WriteText(dir / name, "x");
  test::WriteText(dir / "m.mtl",
                  "newmtl painted\nKd 0.5 0.25 1\nPm 0.75\nPr 0.2\nmap_Kd tex\\ALBEDO.PNG\n"
                  "newmtl shiny\nNs 98\nmap_Pr -bm 1 rough.png\nmap_Pm metal.png\nmap_d mask.png\n"
                  "newmtl plain\n");
  test::WriteText(dir / "m.obj",
                  "mtllib m.mtl\nv 0 0 0\nv 1 0 0\nv 0 1 0\n"
                  "usemtl painted\nf 1 2 3\nusemtl shiny\nf 1 2 3\nusemtl plain\nf 1 2 3\n");
  const ObjModel model = LoadObjModel(dir / "m.obj");
  REQUIRE(model.materials.size() == 3);
  CHECK(model.mesh.materials == std::vector<uint32_t>{0, 1, 2});

  const ObjMaterial& painted = model.materials[0];
  CHECK(painted.material.name == "painted");
  CHECK(painted.material.baseColor == glm::vec3(0.5f, 0.25f, 1.0f));
  CHECK(painted.material.metallic == 0.75f);
  CHECK(painted.material.roughness == 0.2f);
  CHECK(painted.baseColorTexture.filename() == "albedo.png");  // backslash and letter case resolved
  CHECK(fs::equivalent(painted.baseColorTexture, dir / "tex/albedo.png"));
  CHECK(painted.material.baseColorTexture == kNoTexture);

  const ObjMaterial& shiny = model.materials[1];
  CHECK(shiny.material.baseColor == glm::vec3(0.8f));  // no Kd
  CHECK(shiny.material.roughness == 1.0f);             // no Pr, map_Pr given: the texture as is
  CHECK(shiny.material.metallic == 1.0f);
  CHECK(fs::equivalent(shiny.roughnessTexture, dir / "rough.png"));  // "-bm 1" option dropped
  CHECK(fs::equivalent(shiny.metallicTexture, dir / "metal.png"));
  CHECK(fs::equivalent(shiny.alphaTexture, dir / "mask.png"));

  // No Pr, no Ns, no texture.
  CHECK(model.materials[2].material.roughness == 0.5f);
  CHECK(model.materials[2].baseColorTexture.empty());
}

TEST_CASE("roughness comes from Ns when Pr is absent", "[obj]") {
  test::ScratchDir dir("obj-ns");
  test::WriteText(dir / "m.mtl", "newmtl a\nNs 98\nnewmtl b\nNs 0\nPr 0\n");
  test::WriteText(dir / "m.obj", "mtllib m.mtl\nv 0 0 0\nv 1 0 0\nv 0 1 0\nusemtl a\nf 1 2 3\nusemtl b\nf 1 2 3\n");
  const ObjModel model = LoadObjModel(dir / "m.obj");
  CHECK(model.materials[0].material.roughness == Approx(std::sqrt(std::sqrt(2.0f / 100.0f))));
  CHECK(model.materials[1].material.roughness == 0.0f);  // Pr 0 is a value, not an absence
}

TEST_CASE("the Dabrovic Sponza loads with every texture resolved", "[obj][sponza]") {
  const fs::path folder = test::ThirdPartyScenesDir() / "dabrovic-sponza";
  if (!fs::exists(folder / "sponza.obj")) {
    WARN(test::MissingScenesMessage(folder / "sponza.obj"));
    return;
  }
  const ObjModel model = LoadObjModel(folder / "sponza.obj");
  CHECK(model.mesh.TriangleCount() == 66450);
  REQUIRE(model.materials.size() == 20);  // every face has a material: no default added
  for (const ObjMaterial& m : model.materials) {
    INFO(m.material.name);
    // sp_01_stub_baza_ is the one material without map_Kd; the others' names differ in case.
    if (m.material.name == "sp_01_stub_baza_") {
      CHECK(m.baseColorTexture.empty());
    } else {
      CHECK(fs::is_regular_file(m.baseColorTexture));
    }
  }
  for (const glm::vec3& n : model.mesh.normals) REQUIRE(IsUnit(n));
}

TEST_CASE("bad OBJ input throws InputError naming the file and line", "[obj][errors]") {
  test::ScratchDir dir("obj-errors");
  const std::string triangle = "v 0 0 0\nv 1 0 0\nv 0 1 0\n";
  auto errorFor = [&](const std::string& name, const std::string& text) {
    test::WriteText(dir / name, text);
    return LoadError(dir / name);
  };

  CHECK_THAT(errorFor("nan.obj", "v 0 0 0\nv 1 0 0\nv nan 1 0\nf 1 2 3\n"), Catch::Contains("nan.obj:3:"));
  CHECK_THAT(errorFor("crlf.obj", "v 0 0 0\r\nv 1 0 0\r\n\r\nv 0 1 -nan\r\nf 1 2 3\r\n"),
             Catch::Contains("crlf.obj:4:"));
  CHECK_THAT(errorFor("inf.obj", "v 0 0 0\nv 1 inf 0\nv 0 1 0\nf 1 2 3\n"), Catch::Contains("inf.obj:2:"));
  CHECK_THAT(errorFor("huge.obj", "v 0 0 0\nv 1 0 0\nv 0 1e39 0\nf 1 2 3\n"), Catch::Contains("huge.obj:3:"));
  CHECK_THAT(errorFor("nanvn.obj", triangle + "vn 0 0 NaN\nf 1//1 2//1 3//1\n"), Catch::Contains("nanvn.obj:4:"));
  CHECK_THAT(errorFor("infvt.obj", triangle + "vt -inf 0\nf 1/1 2/1 3/1\n"), Catch::Contains("infvt.obj:4:"));
  CHECK_THAT(errorFor("word.obj", triangle + "vt zero 0\nf 1/1 2/1 3/1\n"), Catch::Contains("word.obj:4:"));
  CHECK_THAT(errorFor("short.obj", "v 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n"), Catch::Contains("short.obj:1:"));
  CHECK_THAT(errorFor("range.obj", triangle + "f 1 2 3\nf 1 2 4\n"), Catch::Contains("range.obj:5:"));
  CHECK_THAT(errorFor("rangequad.obj", triangle + "f 1 2 3 9\n"), Catch::Contains("rangequad.obj:4:"));
  CHECK_THAT(errorFor("negative.obj", triangle + "f -1 -2 -4\n"), Catch::Contains("negative.obj:4:"));
  CHECK_THAT(errorFor("zero.obj", triangle + "f 0 1 2\n"), Catch::Contains("zero.obj:4:"));
  CHECK_THAT(errorFor("uvrange.obj", triangle + "vt 0 0\nf 1/1 2/2 3/1\n"), Catch::Contains("uvrange.obj:5:"));
  CHECK_THAT(errorFor("normalrange.obj", triangle + "f 1//1 2//1 3//1\n"), Catch::Contains("normalrange.obj:4:"));
  CHECK_THAT(errorFor("twocorners.obj", triangle + "f 1 2\n"), Catch::Contains("twocorners.obj:4:"));
  CHECK_THAT(errorFor("nofaces.obj", triangle), Catch::Contains("nofaces.obj") && Catch::Contains("no faces"));
  CHECK_THAT(errorFor("empty.obj", ""), Catch::Contains("empty.obj"));
  CHECK_THAT(LoadError(dir / "absent.obj"), Catch::Contains("absent.obj"));

  // A missing MTL is reported by the OBJ that names it; a missing texture by the MTL.
  CHECK_THAT(errorFor("nomtl.obj", "mtllib gone.mtl\n" + triangle + "f 1 2 3\n"),
             Catch::Contains("nomtl.obj:1:") && Catch::Contains("gone.mtl"));
  test::WriteText(dir / "notex.mtl", "newmtl m\nKd 1 1 1\nmap_Kd lost.png\n");
  CHECK_THAT(errorFor("notex.obj", "mtllib notex.mtl\n" + triangle + "usemtl m\nf 1 2 3\n"),
             Catch::Contains("notex.mtl:3:") && Catch::Contains("lost.png"));
}

TEST_CASE("texture names match files case-insensitively", "[obj]") {
  test::ScratchDir dir("obj-case");
  test::WriteText(dir / "Stone_Wall.JPG", "x");
  test::WriteText(dir / "c.mtl", "newmtl wall\nmap_Kd STONE_WALL.jpg\n");
  test::WriteText(dir / "c.obj", "mtllib C.MTL\nv 0 0 0\nv 1 0 0\nv 0 1 0\nusemtl wall\nf 1 2 3\n");
  const ObjModel model = LoadObjModel(dir / "c.obj");
  REQUIRE(model.materials.size() == 1);
  CHECK(model.materials[0].baseColorTexture.filename() == "Stone_Wall.JPG");
  CHECK(model.materials[0].material.baseColor == glm::vec3(1.0f));  // no Kd: the texture as is
}

// A folded strip of three quads (six triangles), every corner up-facing in the consistent file. The
// flipped file winds one triangle the other way round, and writes the last quad with its own copies
// of the shared vertices (as exporters do per object), which must still link by position.
TEST_CASE("inconsistent winding is turned to match the larger part of the surface", "[obj]") {
  test::ScratchDir dir("obj-winding");
  const std::string vertices =
      "v 0 0 0\nv 1 0 0\nv 2 0 0.4\nv 3 0 0\nv 0 1 0\nv 1 1 0\nv 2 1 0.4\nv 3 1 0\n"
      "v 2 0 0.4\nv 2 1 0.4\n";  // 9, 10: copies of 3 and 7
  test::WriteText(dir / "consistent.obj", vertices + "f 1 2 6\nf 1 6 5\nf 2 3 7\nf 2 7 6\nf 3 4 8\nf 3 8 7\n");
  test::WriteText(dir / "flipped.obj", vertices + "f 1 2 6\nf 1 6 5\nf 2 7 3\nf 2 7 6\nf 9 4 8\nf 9 8 10\n");
  const ObjModel consistent = LoadObjModel(dir / "consistent.obj");
  const ObjModel flipped = LoadObjModel(dir / "flipped.obj");
  CHECK(consistent.reorientedTriangles == 0);
  CHECK(flipped.reorientedTriangles == 1);
  REQUIRE(flipped.mesh.TriangleCount() == 6);
  for (size_t t = 0; t < 6; ++t) {
    CAPTURE(t);
    CHECK(FaceNormal(flipped.mesh, t).z > 0.5f);  // every triangle faces up again
    CHECK(glm::dot(FaceNormal(flipped.mesh, t), FaceNormal(consistent.mesh, t)) > 0.9999f);
  }
  // Generated normals are those of the consistent file (smooth across the 22 degree folds), except
  // along x = 2, where the copies are separate vertices to smooth over, as the OBJ has them.
  for (size_t v = 0; v < flipped.mesh.positions.size(); ++v)
    for (size_t c = 0; c < consistent.mesh.positions.size(); ++c)
      if (consistent.mesh.positions[c] == flipped.mesh.positions[v] && flipped.mesh.positions[v].x != 2.0f)
        CHECK(glm::dot(flipped.mesh.normals[v], consistent.mesh.normals[c]) > 0.99999f);
}

}  // namespace
}  // namespace ssgi
