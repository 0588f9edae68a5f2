#include "tests/port/gl_raster.h"

#include <algorithm>
#include <bit>
#include <initializer_list>
#include <memory>

#include "core/check.h"
#include "core/color.h"
#include "core/error.h"
#include "core/raster/raster.h"
#include "core/texture.h"

namespace ssgi::port {
namespace {

// surface.glsl's, raster.glsl's and the passes' bindings.
constexpr GLuint kPositions = 5, kUvs = 6, kIndices = 7, kTriangleMaterials = 8, kMaterials = 9, kTextures = 12,
                 kTexels = 13, kNormals = 10, kSrgbThresholds = 11, kPieces = 3, kPieceCounts = 4, kClosedCulled = 16;
constexpr int kMaxPieces = 7;          // raster.glsl's
constexpr int kSetUpRowLength = 1024;  // raster_setup.comp's triangles per row of invocations

std::vector<float> MaterialRecords(const Scene& scene) {
  std::vector<float> records;
  for (const Material& m : scene.materials) {
    // The port's resolve (gbuffer_conventional.frag) predates them; the port refuses rather than
    // draw another G-buffer than the oracle's (tests/port/README.md).
    for (const int32_t t : {m.baseColorTexture, m.metallicTexture, m.roughnessTexture, m.alphaTexture})
      if (t != kNoTexture && (scene.textures[size_t(t)].wrapU != TextureWrap::kRepeat ||
                              scene.textures[size_t(t)].wrapV != TextureWrap::kRepeat))
        throw InputError(
            scene.source,
            "material '" + m.name + "' has a clamped or mirrored texture, which the GLSL port does not implement");
    if (m.normalTexture != kNoTexture || m.vertexColors)
      throw InputError(
          scene.source,
          "material '" + m.name + "' has a normal map or vertex colours, which the GLSL port does not implement");
    const float fields[8] = {
        m.baseColor.x, m.baseColor.y, m.baseColor.z, m.metallic, m.roughness, m.alphaCutoff, m.twoSided ? 1.0f : 0.0f,
        0.0f};
    records.insert(records.end(), fields, fields + 8);
    const int32_t maps[4] = {m.baseColorTexture, m.metallicTexture, m.roughnessTexture, m.alphaTexture};
    for (int32_t map : maps) records.push_back(std::bit_cast<float>(map));
  }
  return records;
}

// surface.glsl's TextureInfo of every texture, its levels' offsets counted over all the textures'
// texels one after the other.
std::vector<int32_t> TextureInfo(const Scene& scene) {
  std::vector<int32_t> info;
  size_t first = 0;
  for (const Texture& texture : scene.textures) {
    const TextureLevel& base = texture.levels.front();
    info.insert(info.end(), {int32_t(texture.levels.size()), texture.encoding == TextureEncoding::kSrgb ? 0 : 1,
                             texture.sourceChannels, std::max(base.width, base.height)});
    for (size_t k = 0; k < size_t(kMaxTextureLevels); ++k) {
      const bool has = k < texture.levels.size();
      info.insert(info.end(), {has ? texture.levels[k].width : 0, has ? texture.levels[k].height : 0,
                               has ? int32_t(first + texture.levels[k].offset) : 0, 0});
    }
    first += texture.texels.size() / 4;
  }
  return info;
}

std::vector<uint8_t> Texels(const Scene& scene) {
  std::vector<uint8_t> texels;
  for (const Texture& texture : scene.textures)
    texels.insert(texels.end(), texture.texels.begin(), texture.texels.end());
  return texels;
}

template <class T>
Buffer Upload(const std::vector<T>& values) {
  return Buffer(values.size() * sizeof(T) / 4, values.data());
}

// A texture of `format` as a framebuffer attachment; deleted with the object.
class Target {
 public:
  Target(GLenum format, int width, int height) {
    glCreateTextures(GL_TEXTURE_2D, 1, &id_);
    glTextureStorage2D(id_, 1, format, width, height);
  }
  ~Target() { glDeleteTextures(1, &id_); }
  Target(const Target&) = delete;
  Target& operator=(const Target&) = delete;
  GLuint id() const { return id_; }

 private:
  GLuint id_ = 0;
};

}  // namespace

SceneBuffers::SceneBuffers(const Scene& scene)
    : triangles_(scene.mesh.TriangleCount()),
      positions_(Upload(scene.mesh.positions)),
      normals_(Upload(scene.mesh.normals)),
      uvs_(Upload(scene.mesh.uvs)),
      indices_(Upload(scene.mesh.indices)),
      triangleMaterials_(Upload(scene.mesh.materials)),
      materials_(Upload(MaterialRecords(scene))),
      textures_(Upload(TextureInfo(scene))),
      texels_(Upload(Texels(scene))) {}

void SceneBuffers::Bind() const {
  positions_.Bind(kPositions);
  uvs_.Bind(kUvs);
  indices_.Bind(kIndices);
  triangleMaterials_.Bind(kTriangleMaterials);
  materials_.Bind(kMaterials);
  textures_.Bind(kTextures);
  texels_.Bind(kTexels);
  normals_.Bind(kNormals);
}

void SetSurfaceView(const Program& program, const ViewProjection& view) {
  program.SetMatrix("surfaceView", &view.view[0][0]);
  program.Set("orthographicView", view.orthographic ? 1 : 0);
  program.Set("imageSize", view.width, view.height);
  program.Set("tanHalf", view.halfX, view.halfY);
}

namespace {

// A framebuffer of colour attachments and a float32 depth buffer, all width x height; deleted with
// the object.
class Framebuffer {
 public:
  Framebuffer(std::initializer_list<GLenum> colourFormats, int width, int height)
      : width_(width), height_(height), depth_(GL_DEPTH_COMPONENT32F, width, height) {
    glCreateFramebuffers(1, &id_);
    std::vector<GLenum> drawBuffers;
    for (GLenum format : colourFormats) {
      colours_.push_back(std::make_unique<Target>(format, width, height));
      const GLenum attachment = GL_COLOR_ATTACHMENT0 + GLenum(drawBuffers.size());
      glNamedFramebufferTexture(id_, attachment, colours_.back()->id(), 0);
      drawBuffers.push_back(attachment);
    }
    glNamedFramebufferTexture(id_, GL_DEPTH_ATTACHMENT, depth_.id(), 0);
    glNamedFramebufferDrawBuffers(id_, GLsizei(drawBuffers.size()), drawBuffers.data());
    if (glCheckNamedFramebufferStatus(id_, GL_FRAMEBUFFER) != GL_FRAMEBUFFER_COMPLETE)
      throw GlError("a framebuffer of the port's raster passes is incomplete");
    const float zero[4] = {0.0f, 0.0f, 0.0f, 0.0f};
    glClearNamedFramebufferfv(id_, GL_DEPTH, 0, zero);
  }
  ~Framebuffer() { glDeleteFramebuffers(1, &id_); }
  Framebuffer(const Framebuffer&) = delete;
  Framebuffer& operator=(const Framebuffer&) = delete;

  void Clear(int attachment, const GLuint (&value)[4]) const {
    glClearNamedFramebufferuiv(id_, GL_COLOR, attachment, value);
  }
  void Clear(int attachment, const float (&value)[4]) const {
    glClearNamedFramebufferfv(id_, GL_COLOR, attachment, value);
  }

  // Every triangle of `scene` in one draw (so gl_PrimitiveID is the mesh's triangle index), its
  // vertices pulled by `program` with gl_VertexID: reversed Z in [0, 1] (clip 0 <= z <= w, the
  // oracle's far and near planes), rows from the top (the upper-left clip origin), depth tested
  // GREATER against 0.
  void Draw(const Program& program, const SceneBuffers& scene) const {
    glClipControl(GL_UPPER_LEFT, GL_ZERO_TO_ONE);
    glBindFramebuffer(GL_DRAW_FRAMEBUFFER, id_);
    glViewport(0, 0, width_, height_);
    glEnable(GL_DEPTH_TEST);
    glDepthFunc(GL_GREATER);
    glDisable(GL_CULL_FACE);
    GLuint vertexArray = 0;
    glCreateVertexArrays(1, &vertexArray);
    glVertexArrayElementBuffer(vertexArray, scene.indices().id());
    glBindVertexArray(vertexArray);
    glUseProgram(program.id());
    glDrawElements(GL_TRIANGLES, GLsizei(3 * scene.triangles()), GL_UNSIGNED_INT, nullptr);
    glBindVertexArray(0);
    glDeleteVertexArrays(1, &vertexArray);
    glBindFramebuffer(GL_DRAW_FRAMEBUFFER, 0);
    glDisable(GL_DEPTH_TEST);
    glClipControl(GL_LOWER_LEFT, GL_NEGATIVE_ONE_TO_ONE);
  }

  // One channel (`format`: GL_RED, GL_RED_INTEGER, GL_GREEN_INTEGER, ...) of colour attachment
  // `attachment` into a buffer, rows from the top.
  Buffer Read(int attachment, GLenum format, GLenum type) const {
    Buffer out(size_t(width_) * size_t(height_));
    glNamedFramebufferReadBuffer(id_, GL_COLOR_ATTACHMENT0 + GLenum(attachment));
    glBindFramebuffer(GL_READ_FRAMEBUFFER, id_);
    glBindBuffer(GL_PIXEL_PACK_BUFFER, out.id());
    glPixelStorei(GL_PACK_ALIGNMENT, 4);
    glReadPixels(0, 0, width_, height_, format, type, nullptr);
    glBindBuffer(GL_PIXEL_PACK_BUFFER, 0);
    glBindFramebuffer(GL_READ_FRAMEBUFFER, 0);
    glMemoryBarrier(GL_SHADER_STORAGE_BARRIER_BIT);
    return out;
  }

 private:
  int width_, height_;
  Target depth_;
  std::vector<std::unique_ptr<Target>> colours_;
  GLuint id_ = 0;
};

// raster.glsl's closedCulled: the triangles `marked` marks (empty: none), one word each.
Buffer ClosedCulledBuffer(size_t triangles, const std::vector<uint32_t>& marked) {
  SSGI_CHECK(marked.empty() || marked.size() == triangles);
  if (!marked.empty()) return Buffer(marked.size(), marked.data());
  const std::vector<uint32_t> none(std::max<size_t>(1, triangles), 0u);
  return Buffer(none.size(), none.data());
}

// raster.glsl's oracle set-up of every triangle seen from `view`, bound where it reads it.
struct RasterSetUp {
  RasterSetUp(const SceneBuffers& scene, const ViewProjection& view, bool cullBackFaces,
              const std::vector<uint32_t>& closedCulledTriangles)
      : pieces(scene.triangles() * kMaxPieces * 16),
        counts(scene.triangles()),
        closedCulled(ClosedCulledBuffer(scene.triangles(), closedCulledTriangles)) {
    scene.Bind();
    pieces.Bind(kPieces);
    counts.Bind(kPieceCounts);
    closedCulled.Bind(kClosedCulled);
    const Program setUp("raster_setup.comp", {"surface.glsl", "raster.glsl"});
    SetRasterView(setUp, view);
    setUp.Set("triangleCount", int(scene.triangles()));
    setUp.Set("rowLength", kSetUpRowLength);
    setUp.Set("cullBackFaces", cullBackFaces ? 1 : 0);
    setUp.Dispatch(kSetUpRowLength, int((scene.triangles() + kSetUpRowLength - 1) / kSetUpRowLength));
  }
  Buffer pieces, counts, closedCulled;
};

}  // namespace

void SetRasterView(const Program& program, const ViewProjection& view, int snapBits) {
  SetSurfaceView(program, view);
  program.Set("rasterSize", view.width, view.height);
  program.SetMatrix("viewProjection", &view.viewProjection[0][0]);
  program.Set("snapBits", snapBits);
}

VisibilityTargets RunVisibilityPass(const SceneBuffers& scene, const ViewProjection& view, bool cullBackFaces,
                                    RasterKind kind, int snapBits, const std::vector<uint32_t>& closedCulled) {
  const RasterSetUp setUp(scene, view, cullBackFaces, closedCulled);
  const Program draw("visibility.vert", "visibility.frag", {"surface.glsl", "raster.glsl"});
  SetRasterView(draw, view, snapBits);
  draw.Set("cullBackFaces", cullBackFaces ? 1 : 0);
  const Framebuffer target({GL_R32UI, GL_R32F}, view.width, view.height);
  target.Clear(0, {kNoTriangle, 0u, 0u, 0u});
  target.Clear(1, {0.0f, 0.0f, 0.0f, 0.0f});
  target.Draw(draw, scene);
  return {kind == RasterKind::kVisibility ? target.Read(0, GL_RED_INTEGER, GL_UNSIGNED_INT) : Buffer(0),
          target.Read(1, GL_RED, GL_FLOAT)};
}

namespace {

PortGBuffer ResolveGBuffer(const SceneBuffers& scene, const ViewProjection& camera, NormalEncoding encoding,
                           float specularAaKappa, int snapBits) {
  PortGBuffer out{{}, RunVisibilityPass(scene, camera, true, RasterKind::kVisibility, snapBits)};
  const size_t pixels = size_t(camera.width) * size_t(camera.height);
  for (int w = 0; w < 3; ++w) out.words.emplace_back(pixels);
  const Program resolve("gbuffer_resolve.comp", {"surface.glsl", "gbuffer_pack.glsl"});
  SetSurfaceView(resolve, camera);
  resolve.Set("normalEncoding", encoding == NormalEncoding::kXyz8 ? 0 : 1);
  resolve.Set("specularAaKappa", specularAaKappa);
  resolve.Set("nearPlane", camera.nearPlane);
  const Buffer thresholds(255, SrgbEncodeThresholds());
  thresholds.Bind(kSrgbThresholds);
  scene.Bind();
  out.visibility.triangle.Bind(0);
  out.visibility.depthKey.Bind(1);
  for (GLuint w = 0; w < 3; ++w) out.words[w].Bind(2 + w);
  resolve.Dispatch(camera.width, camera.height);
  return out;
}

PortGBuffer ConventionalGBuffer(const SceneBuffers& scene, const ViewProjection& camera, NormalEncoding encoding,
                                float specularAaKappa, int snapBits) {
  scene.Bind();
  const Buffer thresholds(255, SrgbEncodeThresholds());
  thresholds.Bind(kSrgbThresholds);
  const Program draw("gbuffer_conventional.vert", "gbuffer_conventional.frag",
                     {"surface.glsl", "raster.glsl", "gbuffer_pack.glsl"});
  SetRasterView(draw, camera, snapBits);
  draw.Set("cullBackFaces", 1);
  draw.Set("normalEncoding", encoding == NormalEncoding::kXyz8 ? 0 : 1);
  draw.Set("specularAaKappa", specularAaKappa);
  const Framebuffer target({GL_RGBA32UI, GL_R32UI}, camera.width, camera.height);
  target.Clear(0, {0u, 0u, 0x7F800000u, 0u});  // background: words 0, 0, +inf, lit
  target.Clear(1, {kNoTriangle, 0u, 0u, 0u});
  target.Draw(draw, scene);
  PortGBuffer out{{}, {target.Read(1, GL_RED_INTEGER, GL_UNSIGNED_INT), Buffer(0)}};
  for (GLenum channel : {GL_RED_INTEGER, GL_GREEN_INTEGER, GL_BLUE_INTEGER})
    out.words.push_back(target.Read(0, channel, GL_UNSIGNED_INT));
  return out;
}

}  // namespace

PortGBuffer RunGBufferPass(const SceneBuffers& scene, const ViewProjection& camera, NormalEncoding encoding,
                           float specularAaKappa, GBufferForm form, int snapBits) {
  return form == GBufferForm::kVisibility ? ResolveGBuffer(scene, camera, encoding, specularAaKappa, snapBits)
                                          : ConventionalGBuffer(scene, camera, encoding, specularAaKappa, snapBits);
}

}  // namespace ssgi::port
