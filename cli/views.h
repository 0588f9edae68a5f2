// `ssgi render-views`: many views of one scene, each rendered into the buffers of the one before
// (BufferLifetime::kKeepForReuse), written on a thread of their own while the next view renders,
// and delivered into a manifest that lets an interrupted run resume. cli/views_mpi.cpp spreads the
// same work over the ranks of an MPI job.
#pragma once

#include <condition_variable>
#include <cstdio>
#include <deque>
#include <filesystem>
#include <functional>
#include <map>
#include <memory>
#include <mutex>
#include <optional>
#include <set>
#include <string>
#include <thread>
#include <vector>

#include "cli/image_transfer.h"
#include "cli/progress.h"
#include "core/scene.h"
#include "core/system_memory.h"
#include "passes/frame/config.h"
#include "passes/frame/frame.h"

namespace ssgi::cli {

namespace fs = std::filesystem;

// The output names: a printf pattern with exactly one integer conversion (%d, %04d, %5d; "%%" is a
// literal %) in the file name, which takes the view's index; .png or .exr.
class ViewOutputPattern {
 public:
  // Throws InputError naming the pattern and what is wrong with it.
  explicit ViewOutputPattern(std::string pattern);
  fs::path Path(int index) const;
  ImageFileKind Kind() const { return kind_; }
  fs::path Folder() const;
  const std::string& Text() const { return pattern_; }

 private:
  std::string pattern_;
  ImageFileKind kind_ = ImageFileKind::kPng;
};

// Renders views of one scene into one frame it keeps, so that every view after the first renders
// into the buffers of the one before. Not thread-safe: one renderer per rendering thread.
class ViewRenderer {
 public:
  // `scene` is changed (its camera, the first directional light's direction) view by view.
  ViewRenderer(Scene& scene, const FrameConfig& config, ImageFileKind kind, const MemoryBudget& budget);
  // Renders `view` (the views file's view number `index`) into `image`, whose buffers are reused:
  // a PNG's display image trades places with image.rgb8. A view that cannot render (its own error,
  // a light direction without a light, a size over the memory budget) comes back with image.error.
  void Render(const ViewSpec& view, int index, ViewImage& image);
  const Frame& frame() const { return frame_; }

 private:
  Scene& scene_;
  FrameConfig config_;
  ImageFileKind kind_;
  MemoryBudget budget_;
  CameraDesc sceneCamera_;
  std::optional<glm::vec3> sceneLight_;
  // A sky whose sun follows the first light (no sun_direction in the scene file) follows a view's
  // light direction too, as it would in a scene file with that light: the last one made is kept.
  bool sunFollowsLight_ = false;
  std::optional<std::pair<glm::vec3, Environment>> litSky_;
  std::map<std::pair<int, int>, std::string> refusedSizes_;  // "" where the size fits the budget
  Frame frame_;
};

// Writes view images on a thread of its own, each atomically (cli/output_files.h), so that writing
// one view overlaps rendering the next. Images travel by swapping buffers: nothing is copied.
class ViewWriter {
 public:
  // Called on the writer's thread after each image is written (writeError empty) or could not be
  // (the image's own error, or the write's).
  using Delivered = std::function<void(const ViewImage& image, const std::string& writeError, double writeMs)>;
  ViewWriter(ViewOutputPattern pattern, Delivered delivered, size_t queueDepth = 2);
  ~ViewWriter();
  ViewWriter(const ViewWriter&) = delete;
  ViewWriter& operator=(const ViewWriter&) = delete;

  // Queues `image` to be written and hands back, in `image`, the buffers of one written before (or
  // empty ones); waits while queueDepth images are waiting.
  void Push(ViewImage& image);
  // Waits until every queued image is written; rethrows what the writer's callback threw.
  void Finish();

 private:
  void Run();

  ViewOutputPattern pattern_;
  Delivered delivered_;
  size_t depth_;
  std::mutex mutex_;
  std::condition_variable changed_;
  std::deque<ViewImage> queue_;
  std::vector<ViewImage> free_;
  bool writing_ = false, stop_ = false;
  std::exception_ptr failure_;
  std::thread thread_;
};

// What a run of render-views is: the same on every rank.
struct ViewsJob {
  fs::path scenePath, viewsPath;
  std::vector<ViewSpec> views;
  std::optional<ViewOutputPattern> pattern;
  fs::path manifest;
  bool resume = false;
  TransferEncoding encoding = TransferEncoding::kLz4;
  int jpegQuality = 90;
  bool writeOnRank = false;
  MemoryBudget budget;
};

// The manifest of delivered views (JSON: the job's identity and the sorted indices), rewritten
// atomically after each delivery by the one process that delivers (rank 0).
class ViewsManifest {
 public:
  ViewsManifest(const ViewsJob& job);
  // The views a resumed run still renders: those not in the manifest, or whose image is gone.
  // Throws InputError when the manifest belongs to another job (another scene, views file, output
  // pattern or view count). Without --resume, every view.
  std::vector<int> Missing() const;
  void MarkDelivered(int index);

 private:
  void Save() const;
  const ViewsJob& job_;
  std::set<int> delivered_;
};

// What rank 0 (or the one process) learns as views are delivered: the progress line, failures
// reported by index as they happen, the manifest, and the transfer's figures. Thread-safe.
class ViewsDelivery {
 public:
  ViewsDelivery(const ViewsJob& job, ViewsManifest& manifest, size_t total);
  void Delivered(const ViewImage& image, const std::string& writeError);
  void Transferred(const TransferTimes& times);
  // The summary lines, and the exit code: 0 when every view was delivered, 1 when some failed.
  int Report(double seconds, int ranks, int threads);

 private:
  const ViewsJob& job_;
  ViewsManifest& manifest_;
  std::mutex mutex_;
  Progress progress_;
  size_t total_, done_ = 0;
  std::vector<std::pair<int, std::string>> failed_;
  double renderMs_ = 0.0;
  size_t transfers_ = 0;
  TransferTimes transfer_;  // summed
};

// Renders job.views' `todo` in this process: the caller's thread renders, a writer thread writes.
void RenderViewsHere(Scene& scene, const FrameConfig& config, const ViewsJob& job, const std::vector<int>& todo,
                     ViewsDelivery& delivery);

// Whether the environment names an MPI launcher's job of more than one rank (mpirun -n K, K > 1):
// the number of ranks, 1 outside one.
int LaunchedRanks();

// This process's part of an MPI job (cli/views_mpi.cpp): MPI is started (MPI_Init_thread,
// MPI_THREAD_FUNNELED: only the main thread calls MPI) when the object is made and finalized when it
// dies. Rank 0 hands out the views one at a time as ranks ask (views differ in cost) and renders
// too; the other ranks render what they are given and send the images to rank 0, or write them
// themselves and send only the news (--write-on-rank).
struct PreparedRanks {
  bool all = true, rankZero = true;
};
class MpiViews {
 public:
  // Throws InputError in a build without MPI.
  MpiViews();
  ~MpiViews();
  MpiViews(const MpiViews&) = delete;
  MpiViews& operator=(const MpiViews&) = delete;
  int rank() const { return rank_; }
  int size() const { return size_; }
  // Whether every rank prepared the job, and whether rank 0 did (each passes its own outcome).
  PreparedRanks AllPrepared(bool prepared);
  // Runs the job: on rank 0 `todo` are the views to render and `delivery` hears of each; the other
  // ranks pass neither. Any failure ends the whole job (MPI_Abort), as a dead rank does.
  void Run(Scene& scene, const FrameConfig& config, const ViewsJob& job, const std::vector<int>& todo,
           ViewsDelivery* delivery);

 private:
  int rank_ = 0, size_ = 1;
};

}  // namespace ssgi::cli
