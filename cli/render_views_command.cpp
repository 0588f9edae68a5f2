// `ssgi render-views`: many views of one scene (a views file), rendered into reused buffers, in one
// process or over the ranks of an MPI job (cli/views.h).
#include <cstdio>
#include <memory>

#include "cli/command_line_errors.h"
#include "cli/commands.h"
#include "cli/output_files.h"
#include "cli/views.h"
#include "core/error.h"
#include "core/parallel.h"
#include "core/stopwatch.h"

namespace ssgi::cli {
namespace {

struct RenderViewsOptions {
  std::string scene;
  std::string views;
  std::string output;
  std::string manifest;
  int threads = 0;
  bool resume = false;
  std::string encoding = "lz4";
  int jpegQuality = 90;
  bool writeOnRank = false;
  std::string maxMemory;
  SettingOptions settings;
};

TransferEncoding ParseEncoding(const std::string& name) {
  if (name == "raw") return TransferEncoding::kRaw;
  if (name == "jpeg") return TransferEncoding::kJpeg;
  return TransferEncoding::kLz4;
}

// What every rank prepares alike from the command line; rank 0 also reads the manifest and makes the
// output folder.
struct Prepared {
  ViewsJob job;
  Scene scene;
  FrameConfig config;
  std::optional<ViewsManifest> manifest;
  std::optional<CreatedFolder> folder;
  std::vector<int> todo;
};

void Prepare(const RenderViewsOptions& options, int rank, Prepared& p) {
  ViewsJob& job = p.job;
  job.scenePath = options.scene.empty() ? DefaultScenePath() : fs::path(options.scene);
  job.viewsPath = options.views;
  job.pattern.emplace(options.output);
  job.encoding = ParseEncoding(options.encoding);
  job.jpegQuality = options.jpegQuality;
  job.writeOnRank = options.writeOnRank;
  job.resume = options.resume;
  if (job.encoding == TransferEncoding::kJpeg && job.pattern->Kind() == ImageFileKind::kExr)
    throw InputError("--encoding jpeg carries 8-bit images: use lz4 or raw for .exr output");
  CheckInputFile(job.viewsPath, "views");
  CheckInputFile(job.scenePath, "scene");
  job.views = LoadViewsFile(job.viewsPath);
  job.manifest = options.manifest.empty() ? job.pattern->Folder() / "manifest.json" : fs::path(options.manifest);
  job.budget = BudgetFor(options.maxMemory);
  SceneAndConfig loaded = LoadSceneAndConfig(job.scenePath, options.settings);
  p.scene = std::move(loaded.scene);
  p.config = loaded.config;
  if (rank == 0) {
    // The folder, and whether images can be written there, before any view renders (the other
    // ranks' --write-on-rank writes are checked view by view: the folder is made here).
    p.folder.emplace(job.pattern->Folder());
    RemoveStaleTemporaries(job.pattern->Folder());
    {
      OutputFiles probe;
      probe.Add(job.pattern->Path(0));
    }
    p.manifest.emplace(job);
    OutputFiles probe;
    probe.Add(job.manifest, true);
    p.todo = p.manifest->Missing();
  }
}

int RenderViews(const RenderViewsOptions& options) {
  if (options.output.empty()) throw InputError("-o: the output pattern is empty");
  std::unique_ptr<MpiViews> mpi;
  if (LaunchedRanks() > 1) mpi = std::make_unique<MpiViews>();
  const int rank = mpi ? mpi->rank() : 0;
  const int ranks = mpi ? mpi->size() : 1;
  const ThreadLimit threadLimit(options.threads);
  Prepared p;
  std::exception_ptr failure;
  try {
    Prepare(options, rank, p);
  } catch (...) {
    if (!mpi) throw;
    failure = std::current_exception();
  }
  if (mpi) {
    const PreparedRanks prepared = mpi->AllPrepared(!failure);
    if (!prepared.all) {
      if (rank == 0) {
        if (failure) std::rethrow_exception(failure);
        throw InputError("another rank could not prepare the job (its message is above)");
      }
      // Where rank 0 failed too, its message says it once for all.
      if (failure && prepared.rankZero) {
        try {
          std::rethrow_exception(failure);
        } catch (const std::exception& e) {
          std::fprintf(stderr, "ssgi: error: rank %d: %s\n", rank, Printable(e.what()).c_str());
        }
      }
      return 1;
    }
  }
  const ViewsJob& job = p.job;
  if (rank == 0 && job.resume)
    std::printf("resuming: %zu of %zu views delivered, %zu to render\n", job.views.size() - p.todo.size(),
                job.views.size(), p.todo.size());
  std::optional<ViewsDelivery> delivery;
  if (rank == 0) delivery.emplace(job, *p.manifest, p.todo.size());
  Stopwatch clock;
  if (mpi)
    mpi->Run(p.scene, p.config, job, p.todo, rank == 0 ? &*delivery : nullptr);
  else
    RenderViewsHere(p.scene, p.config, job, p.todo, *delivery);
  if (rank != 0) return 0;
  p.folder->Keep();
  return delivery->Report(clock.Lap() / 1000.0, ranks, ThreadCount(options.threads));
}

}  // namespace

Command AddRenderViewsCommand(CLI::App& app) {
  auto options = std::make_shared<RenderViewsOptions>();
  CLI::App* command = app.add_subcommand(
      "render-views",
      "Render many views of a scene (a views file: cameras, or a camera path) into reused buffers, one image per "
      "view; under mpirun the views are shared out over the ranks.");
  command->add_option("scene", options->scene, "Scene file (.json) or OBJ model. Default: the built-in default scene.");
  command
      ->add_option("--views", options->views,
                   "Views file (.json, see docs/user-guide.md 'Views files'): \"views\", a list of cameras with "
                   "optional size and light_direction, or \"path\", camera keyframes and a frame count.")
      ->required();
  command
      ->add_option("-o,--output", options->output,
                   "Output pattern with one %d for the view's number, such as 'out/view_%04d.png' (.png or .exr). "
                   "A missing folder is created.")
      ->required();
  command->add_option("--manifest", options->manifest,
                      "The manifest of delivered views, rewritten after each. Default: manifest.json in the output "
                      "folder.");
  command->add_flag("--resume", options->resume,
                    "Render only the views the manifest does not list (or whose image is gone), after an "
                    "interrupted run.");
  AddThreadsOption(*command, options->threads,
                   "Worker threads per process (per rank under mpirun; 0 = all hardware threads). The images are "
                   "byte-identical for any count.");
  command
      ->add_option("--encoding", options->encoding,
                   "How ranks send images to rank 0: raw, lz4 (lossless) or jpeg (lossy, PNG output only). "
                   "Default: lz4.")
      ->check(CLI::IsMember({"raw", "lz4", "jpeg"}));
  command->add_option("--jpeg-quality", options->jpegQuality, "JPEG quality of --encoding jpeg, 1-100. Default: 90.")
      ->check(CLI::Range(1, 100));
  command->add_flag("--write-on-rank", options->writeOnRank,
                    "Each rank writes its own images (to storage every rank sees) and sends rank 0 only the news.");
  AddMaxMemoryOption(*command, options->maxMemory);
  options->settings.Register(*command);
  return {command, [options] { return RenderViews(*options); }};
}

}  // namespace ssgi::cli
