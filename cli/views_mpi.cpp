// render-views over MPI (cli/views.h, MpiViews). Built with MPI when CMake finds it (SSGI_HAVE_MPI);
// without it, MpiViews refuses to start and render-views runs in one process.
#include <chrono>
#include <cstdio>
#include <exception>
#include <thread>

#include "cli/command_line_errors.h"
#include "cli/views.h"
#include "core/error.h"

#ifdef SSGI_HAVE_MPI
#include <mpi.h>
#endif

namespace ssgi::cli {

#ifndef SSGI_HAVE_MPI

MpiViews::MpiViews() {
  throw InputError(
      "this ssgi was built without MPI (install libopenmpi-dev and build again): run render-views "
      "without mpirun to render every view in one process");
}
MpiViews::~MpiViews() = default;
PreparedRanks MpiViews::AllPrepared(bool prepared) { return {prepared, prepared}; }
void MpiViews::Run(Scene&, const FrameConfig&, const ViewsJob&, const std::vector<int>&, ViewsDelivery*) {}

#else

namespace {

enum Tag : int {
  kRequest = 1,  // a rank asks rank 0 for a view (no data)
  kAssign = 2,   // rank 0's answer: the view's index, or -1 when none is left
  kImage = 3,    // a rendered view (cli/image_transfer.h's message), for rank 0 to write
  kWritten = 4,  // --write-on-rank: a view the rank wrote (or that failed), the same message without pixels
  kBye = 5,      // a rank has sent everything
};

// Open MPI's blocking calls spin on a core while they wait; on a machine whose cores all render,
// the waits poll instead and sleep in between. A message waits at most this long to be seen, short
// against a frame's tens of milliseconds.
constexpr auto kPollInterval = std::chrono::microseconds(100);

// The views rank 0 has not handed out yet, taken by its own rendering thread and by the other ranks.
class ViewQueue {
 public:
  explicit ViewQueue(const std::vector<int>& todo) : todo_(todo) {}
  int Take() {
    std::lock_guard lock(mutex_);
    return next_ < todo_.size() ? todo_[next_++] : -1;
  }

 private:
  std::mutex mutex_;
  const std::vector<int>& todo_;
  size_t next_ = 0;
};

// Between a worker rank's main thread (MPI) and its rendering thread.
struct Mailbox {
  std::mutex mutex;
  std::condition_variable changed;
  std::deque<int> inbox;         // views given to this rank, not yet started
  bool noMore = false;           // rank 0 has no view left
  bool rendering = false;        // the rendering thread is on a view
  bool renderDone = false;       // the rendering thread has ended
  std::deque<ViewImage> images;  // rendered, to send to rank 0
  std::deque<ViewImage> notes;   // --write-on-rank: written (or failed), to report to rank 0
  std::vector<ViewImage> spare;  // sent: their buffers are reused
  std::exception_ptr failure;
};

void Check(int code, const char* call) {
  if (code != MPI_SUCCESS) throw std::runtime_error(std::string("MPI: ") + call + " failed");
}

// The rendering thread of a rank: renders the views `next` gives until it gives -1; each image goes
// to `deliver`, which hands back buffers to reuse in its argument.
template <class Next, class Deliver>
void RenderLoop(ViewRenderer& renderer, const ViewsJob& job, Next&& next, Deliver&& deliver) {
  ViewImage image;
  for (int index = next(); index >= 0; index = next()) {
    renderer.Render(job.views[size_t(index)], index, image);
    deliver(image);
  }
}

void RunRankZero(int ranks, Scene& scene, const FrameConfig& config, const ViewsJob& job, const std::vector<int>& todo,
                 ViewsDelivery& delivery) {
  ViewQueue queue(todo);
  ViewWriter writer(*job.pattern, [&](const ViewImage& image, const std::string& writeError, double) {
    delivery.Delivered(image, writeError);
  });
  std::exception_ptr renderFailure;
  std::thread renderThread([&] {
    try {
      ViewRenderer renderer(scene, config, job.pattern->Kind(), job.budget);
      RenderLoop(
          renderer, job, [&] { return queue.Take(); }, [&](ViewImage& image) { writer.Push(image); });
    } catch (...) {
      renderFailure = std::current_exception();
    }
  });
  std::vector<uint8_t> message;
  ViewImage received;
  int byes = 0;
  try {
    while (byes < ranks - 1) {
      int flag = 0;
      MPI_Status status;
      Check(MPI_Iprobe(MPI_ANY_SOURCE, MPI_ANY_TAG, MPI_COMM_WORLD, &flag, &status), "MPI_Iprobe");
      if (!flag) {
        std::this_thread::sleep_for(kPollInterval);
        continue;
      }
      int bytes = 0;
      Check(MPI_Get_count(&status, MPI_BYTE, &bytes), "MPI_Get_count");
      message.resize(size_t(bytes));
      Check(MPI_Recv(message.data(), bytes, MPI_BYTE, status.MPI_SOURCE, status.MPI_TAG, MPI_COMM_WORLD,
                     MPI_STATUS_IGNORE),
            "MPI_Recv");
      switch (status.MPI_TAG) {
        case kRequest: {
          const int index = queue.Take();
          Check(MPI_Send(&index, 1, MPI_INT, status.MPI_SOURCE, kAssign, MPI_COMM_WORLD), "MPI_Send");
          break;
        }
        case kImage: {
          TransferTimes times;
          DecodeViewImage(message, received, times);
          if (received.error.empty()) delivery.Transferred(times);
          writer.Push(received);
          break;
        }
        case kWritten: {
          TransferTimes times;
          DecodeViewImage(message, received, times);
          delivery.Delivered(received, "");
          break;
        }
        case kBye:
          ++byes;
          break;
        default:
          throw std::runtime_error("MPI: a message with an unknown tag " + std::to_string(status.MPI_TAG));
      }
    }
  } catch (...) {
    renderThread.join();
    throw;
  }
  renderThread.join();
  if (renderFailure) std::rethrow_exception(renderFailure);
  writer.Finish();
}

void RunWorker(Scene& scene, const FrameConfig& config, const ViewsJob& job) {
  Mailbox box;
  std::thread renderThread([&] {
    try {
      ViewRenderer renderer(scene, config, job.pattern->Kind(), job.budget);
      std::optional<ViewWriter> writer;
      if (job.writeOnRank)
        writer.emplace(*job.pattern, [&](const ViewImage& image, const std::string& writeError, double) {
          ViewImage note;
          note.index = image.index;
          note.kind = image.kind;
          note.renderMs = image.renderMs;
          note.error = image.error.empty() ? writeError : image.error;
          std::lock_guard lock(box.mutex);
          box.notes.push_back(std::move(note));
          box.changed.notify_all();
        });
      const auto next = [&] {
        std::unique_lock lock(box.mutex);
        box.rendering = false;
        box.changed.notify_all();
        box.changed.wait(lock, [&] { return !box.inbox.empty() || box.noMore; });
        if (box.inbox.empty()) return -1;
        const int index = box.inbox.front();
        box.inbox.pop_front();
        box.rendering = true;
        return index;
      };
      const auto deliver = [&](ViewImage& image) {
        if (writer) return writer->Push(image);
        std::unique_lock lock(box.mutex);
        // At most two images wait to be sent: their buffers then come back.
        box.changed.wait(lock, [&] { return box.images.size() < 2; });
        box.images.push_back(std::move(image));
        image = ViewImage{};
        if (!box.spare.empty()) {
          image = std::move(box.spare.back());
          box.spare.pop_back();
        }
        box.changed.notify_all();
      };
      RenderLoop(renderer, job, next, deliver);
      if (writer) writer->Finish();
    } catch (...) {
      std::lock_guard lock(box.mutex);
      box.failure = std::current_exception();
    }
    std::lock_guard lock(box.mutex);
    box.rendering = false;
    box.renderDone = true;
    box.changed.notify_all();
  });

  MPI_Request assignRequest = MPI_REQUEST_NULL, sendRequest = MPI_REQUEST_NULL;
  int assigned = -1;
  std::vector<uint8_t> message;
  try {
    for (;;) {
      bool progressed = false;
      int flag = 0;
      if (assignRequest != MPI_REQUEST_NULL) {
        Check(MPI_Test(&assignRequest, &flag, MPI_STATUS_IGNORE), "MPI_Test");
        if (flag) {
          std::lock_guard lock(box.mutex);
          if (assigned < 0)
            box.noMore = true;
          else
            box.inbox.push_back(assigned);
          box.changed.notify_all();
          progressed = true;
        }
      } else {
        // One view waiting beside the one rendering, so that the renderer never waits for rank 0.
        bool want = false;
        {
          std::lock_guard lock(box.mutex);
          want = !box.noMore && !box.failure && box.inbox.size() + (box.rendering ? 1 : 0) < 2;
        }
        if (want) {
          Check(MPI_Send(nullptr, 0, MPI_BYTE, 0, kRequest, MPI_COMM_WORLD), "MPI_Send");
          Check(MPI_Irecv(&assigned, 1, MPI_INT, 0, kAssign, MPI_COMM_WORLD, &assignRequest), "MPI_Irecv");
          progressed = true;
        }
      }
      if (sendRequest != MPI_REQUEST_NULL) {
        Check(MPI_Test(&sendRequest, &flag, MPI_STATUS_IGNORE), "MPI_Test");
        if (flag) progressed = true;
      }
      if (sendRequest == MPI_REQUEST_NULL) {
        std::optional<ViewImage> image;
        int tag = kImage;
        {
          std::lock_guard lock(box.mutex);
          if (!box.notes.empty()) {
            image = std::move(box.notes.front());
            box.notes.pop_front();
            tag = kWritten;
          } else if (!box.images.empty()) {
            image = std::move(box.images.front());
            box.images.pop_front();
          }
        }
        if (image) {
          EncodeViewImage(*image, job.encoding, job.jpegQuality, message);
          Check(MPI_Isend(message.data(), int(message.size()), MPI_BYTE, 0, tag, MPI_COMM_WORLD, &sendRequest),
                "MPI_Isend");
          std::lock_guard lock(box.mutex);
          if (tag == kImage) box.spare.push_back(std::move(*image));
          box.changed.notify_all();
          progressed = true;
        }
      }
      std::unique_lock lock(box.mutex);
      if (box.failure) std::rethrow_exception(box.failure);
      if (box.renderDone && box.images.empty() && box.notes.empty() && sendRequest == MPI_REQUEST_NULL &&
          assignRequest == MPI_REQUEST_NULL)
        break;
      if (!progressed) box.changed.wait_for(lock, kPollInterval);
    }
  } catch (...) {
    {
      std::lock_guard lock(box.mutex);
      box.noMore = true;
      box.inbox.clear();
      box.changed.notify_all();
    }
    renderThread.join();
    throw;
  }
  renderThread.join();
  Check(MPI_Send(nullptr, 0, MPI_BYTE, 0, kBye, MPI_COMM_WORLD), "MPI_Send");
}

}  // namespace

MpiViews::MpiViews() {
  int provided = 0;
  if (MPI_Init_thread(nullptr, nullptr, MPI_THREAD_FUNNELED, &provided) != MPI_SUCCESS)
    throw InputError("MPI could not start (MPI_Init_thread failed)");
  MPI_Comm_rank(MPI_COMM_WORLD, &rank_);
  MPI_Comm_size(MPI_COMM_WORLD, &size_);
}

MpiViews::~MpiViews() { MPI_Finalize(); }

PreparedRanks MpiViews::AllPrepared(bool prepared) {
  const int mine[2] = {prepared ? 1 : 0, rank_ != 0 || prepared ? 1 : 0};
  int all[2] = {0, 0};
  MPI_Allreduce(mine, all, 2, MPI_INT, MPI_MIN, MPI_COMM_WORLD);
  return {all[0] == 1, all[1] == 1};
}

void MpiViews::Run(Scene& scene, const FrameConfig& config, const ViewsJob& job, const std::vector<int>& todo,
                   ViewsDelivery* delivery) {
  try {
    if (rank_ == 0)
      RunRankZero(size_, scene, config, job, todo, *delivery);
    else
      RunWorker(scene, config, job);
  } catch (const std::exception& e) {
    // Open MPI has no fault-tolerant mode: one rank's failure ends the job, as a dead rank would.
    std::fprintf(stderr, "ssgi: error: rank %d: %s\n", rank_, Printable(e.what()).c_str());
    std::fflush(stderr);
    MPI_Abort(MPI_COMM_WORLD, 1);
  }
}

#endif

}  // namespace ssgi::cli
