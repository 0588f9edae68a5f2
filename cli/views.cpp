#include "cli/views.h"

#include <algorithm>
#include <cctype>
#include <cstdlib>
#include <fstream>
#include <nlohmann/json.hpp>

#include "cli/command_line_errors.h"
#include "cli/common.h"
#include "cli/output_files.h"
#include "core/error.h"
#include "core/image_io.h"
#include "core/stopwatch.h"
#include "passes/frame/memory.h"

namespace ssgi::cli {
namespace {

// Where the one integer conversion of an output pattern is: [begin, end) of "%04d".
struct Conversion {
  size_t begin = std::string::npos, end = std::string::npos;
};

Conversion FindConversion(const std::string& pattern) {
  Conversion found;
  for (size_t i = 0; i < pattern.size(); ++i) {
    if (pattern[i] != '%') continue;
    if (i + 1 < pattern.size() && pattern[i + 1] == '%') {
      ++i;
      continue;
    }
    size_t j = i + 1;
    while (j < pattern.size() && (pattern[j] == '0' || pattern[j] == '-' || pattern[j] == '+' || pattern[j] == ' '))
      ++j;
    while (j < pattern.size() && std::isdigit(static_cast<unsigned char>(pattern[j]))) ++j;
    if (j >= pattern.size() || pattern[j] != 'd' || j - i > 6)
      throw InputError("-o " + pattern +
                       ": the only conversion allowed is one integer such as %d or %04d (%% for a %)");
    if (found.begin != std::string::npos)
      throw InputError("-o " + pattern + ": give one %d for the view's number, not several");
    found = {i, j + 1};
    i = j;
  }
  return found;
}

}  // namespace

ViewOutputPattern::ViewOutputPattern(std::string pattern) : pattern_(std::move(pattern)) {
  if (pattern_.empty()) throw InputError("-o: the output pattern is empty");
  const Conversion conversion = FindConversion(pattern_);
  if (conversion.begin == std::string::npos)
    throw InputError("-o " + pattern_ + ": the output pattern needs a %d (or %04d) for the view's number");
  const size_t slash = pattern_.find_last_of('/');
  if (slash != std::string::npos && slash > conversion.begin)
    throw InputError("-o " + pattern_ + ": the view's number must be in the file name, not in a folder");
  std::string ext = fs::path(pattern_).extension().string();
  for (char& c : ext) c = char(std::tolower(static_cast<unsigned char>(c)));
  if (ext == ".exr")
    kind_ = ImageFileKind::kExr;
  else if (ext != ".png")
    throw InputError("-o " + pattern_ + ": unsupported output format '" + ext + "' (use .png or .exr)");
}

fs::path ViewOutputPattern::Path(int index) const {
  const Conversion c = FindConversion(pattern_);
  const std::string spec = pattern_.substr(c.begin, c.end - c.begin);
  char number[64];
  std::snprintf(number, sizeof(number), spec.c_str(), index);
  std::string text;
  // The literal parts, "%%" read as "%".
  const auto literal = [&](size_t begin, size_t end) {
    for (size_t i = begin; i < end; ++i) {
      text += pattern_[i];
      if (pattern_[i] == '%' && i + 1 < end && pattern_[i + 1] == '%') ++i;
    }
  };
  literal(0, c.begin);
  text += number;
  literal(c.end, pattern_.size());
  return text;
}

fs::path ViewOutputPattern::Folder() const {
  const fs::path folder = fs::path(Path(0)).parent_path();
  return folder.empty() ? fs::path(".") : folder;
}

ViewRenderer::ViewRenderer(Scene& scene, const FrameConfig& config, ImageFileKind kind, const MemoryBudget& budget)
    : scene_(scene), config_(config), kind_(kind), budget_(budget), sceneCamera_(scene.camera) {
  if (!scene.directionalLights.empty()) {
    sceneLight_ = scene.directionalLights.front().direction;
    sunFollowsLight_ = config.environment.kind == EnvironmentKind::kSky &&
                       config.environment.sky.sunDirection == -glm::normalize(*sceneLight_);
  }
}

void ViewRenderer::Render(const ViewSpec& view, int index, ViewImage& image) {
  Stopwatch clock;
  image.index = index;
  image.kind = kind_;
  image.error.clear();
  image.width = image.height = 0;
  if (!view.error.empty()) {
    image.error = view.error;
    return;
  }
  FrameConfig config = config_;
  if (view.width > 0) {
    config.width = view.width;
    config.height = view.height;
  }
  scene_.camera = view.camera;
  if (view.lightDirection) {
    if (!sceneLight_) {
      image.error = "light_direction: the scene has no directional light to turn";
      return;
    }
    scene_.directionalLights.front().direction = *view.lightDirection;
    if (sunFollowsLight_) {
      if (!litSky_ || litSky_->first != *view.lightDirection) {
        SkyParams sky = config_.environment.sky;
        sky.sunDirection = -glm::normalize(*view.lightDirection);
        litSky_.emplace(*view.lightDirection, MakeSkyEnvironment(sky));
      }
      config.environment = litSky_->second;
    }
  } else if (sceneLight_) {
    scene_.directionalLights.front().direction = *sceneLight_;
  }
  // Refused before anything is allocated, as `ssgi render` refuses a frame too large.
  const std::pair<int, int> size{config.width, config.height};
  auto refused = refusedSizes_.find(size);
  if (refused == refusedSizes_.end()) {
    std::string problem;
    try {
      const FrameMemoryEstimate memory = EstimateFrameMemory(scene_, config, BufferLifetime::kKeepForReuse);
      CheckMemory("a " + std::to_string(size.first) + "x" + std::to_string(size.second) + " frame", memory.bytes,
                  budget_, "give the view a smaller size");
    } catch (const InputError& e) {
      problem = e.what();
    }
    refused = refusedSizes_.emplace(size, problem).first;
  }
  if (!refused->second.empty()) {
    image.error = refused->second;
    return;
  }
  try {
    RunFramePasses(scene_, config, FramePass::kGBuffer, FramePass::kTonemap, frame_, BufferLifetime::kKeepForReuse);
  } catch (const InputError& e) {
    image.error = e.what();
    return;
  }
  image.width = config.width;
  image.height = config.height;
  if (kind_ == ImageFileKind::kPng) {
    std::swap(image.rgb8, frame_.display.rgb);
  } else {
    const Plane3<float>& result = frame_.Result();
    const size_t w = size_t(config.width), h = size_t(config.height);
    image.rgb32.resize(3 * w * h);
    for (int c = 0; c < 3; ++c)
      for (size_t y = 0; y < h; ++y)
        std::copy_n(result.c[c].ConstRow(y), w, image.rgb32.data() + (size_t(c) * h + y) * w);
  }
  image.renderMs = clock.Lap();
}

ViewWriter::ViewWriter(ViewOutputPattern pattern, Delivered delivered, size_t queueDepth)
    : pattern_(std::move(pattern)), delivered_(std::move(delivered)), depth_(std::max<size_t>(queueDepth, 1)) {
  thread_ = std::thread([this] { Run(); });
}

ViewWriter::~ViewWriter() {
  {
    std::lock_guard lock(mutex_);
    stop_ = true;
  }
  changed_.notify_all();
  thread_.join();
}

void ViewWriter::Push(ViewImage& image) {
  std::unique_lock lock(mutex_);
  changed_.wait(lock, [&] { return queue_.size() < depth_ || failure_; });
  if (failure_) std::rethrow_exception(failure_);
  queue_.push_back(std::move(image));
  image = ViewImage{};
  if (!free_.empty()) {
    image = std::move(free_.back());
    free_.pop_back();
  }
  changed_.notify_all();
}

void ViewWriter::Finish() {
  std::unique_lock lock(mutex_);
  changed_.wait(lock, [&] { return (queue_.empty() && !writing_) || failure_; });
  if (failure_) std::rethrow_exception(failure_);
}

void ViewWriter::Run() {
  for (;;) {
    ViewImage image;
    {
      std::unique_lock lock(mutex_);
      changed_.wait(lock, [&] { return !queue_.empty() || stop_; });
      if (queue_.empty()) return;
      image = std::move(queue_.front());
      queue_.pop_front();
      writing_ = true;
    }
    Stopwatch clock;
    std::string writeError;
    if (image.error.empty()) {
      const fs::path path = pattern_.Path(image.index);
      try {
        OutputFiles output;
        output.Add(path);
        output.Write(path, [&](const fs::path& temporary) {
          if (image.kind == ImageFileKind::kPng) {
            WritePng(temporary, image.width, image.height, image.rgb8);
          } else {
            const size_t plane = size_t(image.width) * size_t(image.height);
            WriteExr(temporary, image.width, image.height,
                     {{"R", false, image.rgb32.data(), size_t(image.width)},
                      {"G", false, image.rgb32.data() + plane, size_t(image.width)},
                      {"B", false, image.rgb32.data() + 2 * plane, size_t(image.width)}});
          }
        });
        output.Commit();
      } catch (const InputError& e) {
        writeError = e.what();
      }
    }
    const double writeMs = clock.Lap();
    std::exception_ptr failure;
    try {
      delivered_(image, writeError, writeMs);
    } catch (...) {
      failure = std::current_exception();
    }
    {
      std::lock_guard lock(mutex_);
      writing_ = false;
      if (failure && !failure_) failure_ = failure;
      free_.push_back(std::move(image));
    }
    changed_.notify_all();
  }
}

ViewsManifest::ViewsManifest(const ViewsJob& job) : job_(job) {
  if (!job.resume) return;
  std::error_code error;
  if (!fs::exists(job.manifest, error)) return;  // nothing delivered yet: every view is missing
  std::ifstream in(job.manifest);
  nlohmann::json manifest;
  try {
    manifest = nlohmann::json::parse(in);
  } catch (const nlohmann::json::exception& e) {
    throw InputError(job.manifest, std::string("--resume: not a render-views manifest: ") + e.what());
  }
  const auto same = [&](const char* key, const nlohmann::json& value) {
    if (!manifest.is_object() || !manifest.contains(key) || manifest[key] != value)
      throw InputError(job.manifest,
                       std::string("--resume: the manifest is of another run (its ") + key + " is " +
                           (manifest.is_object() && manifest.contains(key) ? manifest[key].dump() : "absent") +
                           ", this run's " + value.dump() + ")");
  };
  same("scene", fs::absolute(job.scenePath).lexically_normal().string());
  same("views_file", fs::absolute(job.viewsPath).lexically_normal().string());
  same("output", job.pattern->Text());
  same("view_count", job.views.size());
  if (!manifest["delivered"].is_array()) throw InputError(job.manifest, "--resume: its delivered list is missing");
  for (const nlohmann::json& index : manifest["delivered"])
    if (index.is_number_integer() && index.get<int64_t>() >= 0 && index.get<int64_t>() < int64_t(job.views.size()))
      delivered_.insert(index.get<int>());
}

std::vector<int> ViewsManifest::Missing() const {
  std::vector<int> missing;
  for (int i = 0; i < int(job_.views.size()); ++i) {
    std::error_code error;
    if (!delivered_.count(i) || !fs::exists(job_.pattern->Path(i), error)) missing.push_back(i);
  }
  return missing;
}

void ViewsManifest::MarkDelivered(int index) {
  delivered_.insert(index);
  Save();
}

void ViewsManifest::Save() const {
  nlohmann::json manifest;
  manifest["scene"] = fs::absolute(job_.scenePath).lexically_normal().string();
  manifest["views_file"] = fs::absolute(job_.viewsPath).lexically_normal().string();
  manifest["output"] = job_.pattern->Text();
  manifest["view_count"] = job_.views.size();
  manifest["delivered"] = delivered_;
  const std::string text = manifest.dump() + "\n";
  OutputFiles output;
  output.Add(job_.manifest, true);
  output.Write(job_.manifest, [&](const fs::path& temporary) {
    std::ofstream out(temporary, std::ios::binary | std::ios::trunc);
    out << text;
    out.close();
    if (!out) throw InputError(temporary, "cannot write the manifest");
  });
  output.Commit();
}

ViewsDelivery::ViewsDelivery(const ViewsJob& job, ViewsManifest& manifest, size_t total)
    : job_(job), manifest_(manifest), progress_("render-views"), total_(total) {}

void ViewsDelivery::Delivered(const ViewImage& image, const std::string& writeError) {
  std::lock_guard lock(mutex_);
  ++done_;
  const std::string& error = image.error.empty() ? writeError : image.error;
  if (error.empty()) {
    manifest_.MarkDelivered(image.index);
    renderMs_ += image.renderMs;
  } else {
    failed_.emplace_back(image.index, error);
    std::fprintf(stderr, "ssgi: view %d failed: %s\n", image.index, Printable(error).c_str());
  }
  const double fraction = total_ ? double(done_) / double(total_) : 1.0;
  progress_.Update(fraction, std::to_string(done_) + " of " + std::to_string(total_) + " views, " +
                                 progress_.RateText(double(done_), "views"));
}

void ViewsDelivery::Transferred(const TransferTimes& times) {
  std::lock_guard lock(mutex_);
  ++transfers_;
  transfer_.rawBytes += times.rawBytes;
  transfer_.encodedBytes += times.encodedBytes;
  transfer_.encodeMs += times.encodeMs;
  transfer_.decodeMs += times.decodeMs;
}

int ViewsDelivery::Report(double seconds, int ranks, int threads) {
  std::lock_guard lock(mutex_);
  const size_t delivered = done_ - failed_.size();
  std::printf("rendered %zu of %zu views in %s (%.2f views/s) on %d %s x %d %s: %s\n", delivered, total_,
              FormatSeconds(seconds).c_str(), seconds > 0.0 ? double(done_) / seconds : 0.0, ranks,
              ranks == 1 ? "process" : "ranks", threads, threads == 1 ? "thread" : "threads",
              job_.pattern->Text().c_str());
  if (delivered > 0) std::printf("  render %.1f ms per view (in the frame)\n", renderMs_ / double(delivered));
  if (transfers_ > 0) {
    const double n = double(transfers_);
    std::printf(
        "  transfer %s: %zu views sent to rank 0, %.1f KiB per view of %.1f KiB raw (%.1fx), encode %.2f ms, "
        "decode %.2f ms per view\n",
        TransferEncodingName(job_.encoding), transfers_, double(transfer_.encodedBytes) / n / 1024.0,
        double(transfer_.rawBytes) / n / 1024.0,
        transfer_.encodedBytes ? double(transfer_.rawBytes) / double(transfer_.encodedBytes) : 0.0,
        transfer_.encodeMs / n, transfer_.decodeMs / n);
  }
  std::printf("  manifest %s\n", job_.manifest.string().c_str());
  if (failed_.empty()) return 0;
  std::sort(failed_.begin(), failed_.end());
  std::string list;
  for (const auto& [index, error] : failed_) list += (list.empty() ? "" : ", ") + std::to_string(index);
  std::fprintf(stderr, "ssgi: error: %zu of %zu views failed (view %s); the others were written\n", failed_.size(),
               total_, list.c_str());
  return 1;
}

void RenderViewsHere(Scene& scene, const FrameConfig& config, const ViewsJob& job, const std::vector<int>& todo,
                     ViewsDelivery& delivery) {
  ViewRenderer renderer(scene, config, job.pattern->Kind(), job.budget);
  ViewWriter writer(*job.pattern, [&](const ViewImage& image, const std::string& writeError, double) {
    delivery.Delivered(image, writeError);
  });
  ViewImage image;
  for (int index : todo) {
    renderer.Render(job.views[size_t(index)], index, image);
    writer.Push(image);
  }
  writer.Finish();
}

int LaunchedRanks() {
  // Open MPI's mpirun, then the PMI variables of other launchers (MPICH's Hydra, Slurm's srun).
  for (const char* variable : {"OMPI_COMM_WORLD_SIZE", "PMI_SIZE", "PMIX_SIZE"})
    if (const char* value = std::getenv(variable)) return std::max(1, std::atoi(value));
  return 1;
}

}  // namespace ssgi::cli
