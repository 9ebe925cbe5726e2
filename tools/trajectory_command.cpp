// `surftrace trajectory`: a molecular surface frame after frame from an MD trajectory, with
// one camera for the whole run, partial updates for the atoms declared flexible, the build of
// frame k+1 overlapped with the drawing of frame k, and frames shared out over processes
// (--shard, Slurm job arrays).
#include <signal.h>
#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <cctype>
#include <cerrno>
#include <atomic>
#include <exception>
#include <chrono>
#include <cmath>
#include <csignal>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <memory>
#include <mutex>
#include <optional>
#include <span>
#include <stdexcept>
#include <vector>

#include <glm/geometric.hpp>
#include <tbb/blocked_range.h>
#include <tbb/enumerable_thread_specific.h>
#include <tbb/parallel_reduce.h>
#include <tbb/parallel_pipeline.h>

#include "commands.hpp"
#include "image_options.hpp"
#include "option_checks.hpp"
#include "pipeline.hpp"
#include "surftrace/camera.hpp"
#include "surftrace/files.hpp"
#include "surftrace/image.hpp"
#include "surftrace/molecule.hpp"
#include "surftrace/surface.hpp"
#include "trajectory_plan.hpp"

namespace surftrace::tools {
namespace {

namespace fs = std::filesystem;

struct TrajectoryOptions {
  std::string topology, trajectory;
  build::ReadOptions read;
  SurfaceOptions surface;
  ImageOptions image;
  view::EngineOptions engine;
  std::string output, exr;
  std::string frames;
  std::string frameCamera = "all";
  std::optional<std::string> flexible;  // given, even as ""
  bool resume = false;
  std::string timings;
  std::string mp4;
  double fps = 25.0;
  std::string shard;
  int threads = 0;
  bool quiet = false;
  std::string commandLine;
};

double millisecondsSince(std::chrono::steady_clock::time_point start) {
  return std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start).count();
}

double median(std::vector<double> v) {
  if (v.empty()) return 0.0;
  std::sort(v.begin(), v.end());
  const std::size_t n = v.size();
  return n % 2 ? v[n / 2] : 0.5 * (v[n / 2 - 1] + v[n / 2]);
}

std::optional<fs::path> findOnPath(const std::string& program) {
  const char* path = std::getenv("PATH");
  if (!path) return std::nullopt;
  std::string_view rest(path);
  while (!rest.empty()) {
    const std::size_t colon = rest.find(':');
    const fs::path candidate = fs::path(std::string(rest.substr(0, colon))) / program;
    if (access(candidate.c_str(), X_OK) == 0) return candidate;
    if (colon == std::string_view::npos) break;
    rest.remove_prefix(colon + 1);
  }
  return std::nullopt;
}

// Runs a program with arguments (no shell); its exit status.
int runProgram(const std::vector<std::string>& argv) {
  std::vector<char*> args;
  for (const std::string& a : argv) args.push_back(const_cast<char*>(a.c_str()));
  args.push_back(nullptr);
  const pid_t pid = fork();
  if (pid < 0) throw std::runtime_error("cannot start " + argv[0]);
  if (pid == 0) {
    std::signal(SIGPIPE, SIG_DFL);  // ignored by surftrace (a closed pipe is its error to report), not by ffmpeg
    execvp(args[0], args.data());
    _exit(127);
  }
  int status = 0;
  while (waitpid(pid, &status, 0) < 0)
    if (errno != EINTR) throw std::runtime_error("waiting for " + argv[0] + " failed");
  return WIFEXITED(status) ? WEXITSTATUS(status) : 128;
}

// Whether a frame's image was written whole by an earlier run (--resume): a PNG ends with its
// IEND chunk, an EXR reads to its last scanline. (Images are written through a temporary file
// and renamed, so a half-written one is rare: a file copied short, a disk that lied.)
bool complete(const std::string& path) {
  if (path.empty()) return true;
  std::error_code ec;
  if (!fs::is_regular_file(path, ec)) return false;
  const std::string ext = fs::path(path).extension().string();
  if (ext == ".png" || ext == ".PNG") {
    static constexpr unsigned char kIend[12] = {0, 0, 0, 0, 'I', 'E', 'N', 'D', 0xAE, 0x42, 0x60, 0x82};
    std::ifstream in(path, std::ios::binary);
    unsigned char tail[12] = {};
    return in.seekg(-12, std::ios::end) && in.read(reinterpret_cast<char*>(tail), 12) &&
           std::memcmp(tail, kIend, 12) == 0;
  }
  try {
    view::readExr(path);
    return true;
  } catch (const std::exception&) {
    return false;
  }
}

// The request's patch list parameters without building it, for framing as `render` frames.
build::PatchList paramsOnly(const build::SurfaceRequest& request) {
  build::PatchList list;
  list.params.surface = request.builtKind();
  list.params.probeRadius = request.probeRadius;
  return list;
}

// The framing of every selected frame's atoms, each reaching `reach` from its centre, as `render`
// frames one structure: one pass over the coordinates, no surface built. DCD and XTC frames are
// read in parallel, one reader a thread (random access, cheap to open); a text trajectory, which
// its reader holds whole in memory, through the trajectory's own reader, a frame at a time. The
// reduction takes only minima and maxima, so the camera does not depend on the threads; every
// shard frames all the selected frames, not only its own, and so computes the same camera. Atoms
// outside --flexible stay where the reference frame has them.
view::SphereFraming frameEveryFrame(build::Trajectory& trajectory, const std::string& path,
                                    const std::vector<std::size_t>& frames, const build::Molecule& reference,
                                    const std::vector<std::uint32_t>& flexible, const std::vector<double>& reach,
                                    const view::SphereFraming& none) {
  const std::vector<std::size_t>& fileIndex = trajectory.fileIndex();
  const auto addFrame = [&](view::SphereFraming& framing, const std::vector<glm::dvec3>& positions) {
    if (flexible.empty()) {
      for (std::size_t i = 0; i < fileIndex.size(); ++i) framing.add(positions[fileIndex[i]], reach[i]);
    } else {
      for (std::uint32_t i : flexible) framing.add(positions[fileIndex[i]], reach[i]);
    }
  };
  const build::TrajectoryFormat format = build::trajectoryFormatFromPath(path);
  const bool randomAccess = format == build::TrajectoryFormat::Dcd || format == build::TrajectoryFormat::Xtc;
  tbb::enumerable_thread_specific<std::unique_ptr<build::FrameSource>> readers;
  tbb::enumerable_thread_specific<build::Frame> buffers;
  std::mutex shared;
  view::SphereFraming framing = tbb::parallel_reduce(
      tbb::blocked_range<std::size_t>(0, frames.size()), none,
      [&](const tbb::blocked_range<std::size_t>& range, view::SphereFraming part) {
        for (std::size_t i = range.begin(); i != range.end(); ++i) {
          if (randomAccess) {
            std::unique_ptr<build::FrameSource>& reader = readers.local();
            if (!reader) reader = build::openTrajectory(path, format);
            build::Frame& frame = buffers.local();
            reader->read(frames[i], frame);
            addFrame(part, frame.positions);
          } else {
            const std::lock_guard lock(shared);
            trajectory.load(frames[i]);
            addFrame(part, trajectory.frame().positions);
          }
        }
        return part;
      },
      [](view::SphereFraming a, const view::SphereFraming& b) {
        a.merge(b);
        return a;
      });
  if (!flexible.empty())
    for (std::size_t i = 0; i < reference.size(); ++i) framing.add(reference.centers[i], reach[i]);
  return framing;
}

// SIGINT and SIGTERM (Ctrl-C; a Slurm time limit, which sends SIGTERM and SIGKILL KillWait
// seconds later, 30 s by default) during the frames: the run takes no new frame, writes those already drawn, says
// where it stopped, and then dies of the signal, as a shell or a job script expects. A second
// signal kills at once (SA_RESETHAND). The handler only records the signal, the one thing it
// may do (nothing else is async-signal-safe); this is the program's one global, because a
// signal handler reaches nothing else.
std::atomic<int> interruptSignal{0};
static_assert(std::atomic<int>::is_always_lock_free, "read and written in a signal handler");

void recordInterrupt(int signal) { interruptSignal.store(signal); }

// Catches SIGINT and SIGTERM while it lives.
class InterruptHandler {
 public:
  InterruptHandler() {
    struct sigaction action {};
    action.sa_handler = recordInterrupt;
    sigemptyset(&action.sa_mask);
    action.sa_flags = SA_RESTART | SA_RESETHAND;
    sigaction(SIGINT, &action, &previousInt_);
    sigaction(SIGTERM, &action, &previousTerm_);
    // A signal ignored on entry stays ignored (a background job of a script, nohup).
    if (previousInt_.sa_handler == SIG_IGN) sigaction(SIGINT, &previousInt_, nullptr);
    if (previousTerm_.sa_handler == SIG_IGN) sigaction(SIGTERM, &previousTerm_, nullptr);
  }
  ~InterruptHandler() {
    sigaction(SIGINT, &previousInt_, nullptr);
    sigaction(SIGTERM, &previousTerm_, nullptr);
  }
  InterruptHandler(const InterruptHandler&) = delete;
  InterruptHandler& operator=(const InterruptHandler&) = delete;

  static int signal() { return interruptSignal.load(); }

 private:
  struct sigaction previousInt_ {}, previousTerm_ {};
};

// zlib's level for the frames' PNGs: level 1 encodes AdK's 512x512 frames in about two thirds
// of the time of the default 6 (the conversion to 8 bits and OpenImageIO's share stay) for files
// 7% larger, and the pixels are the same (README, Benchmarks). A movie's frames are many and are
// read once, by ffmpeg.
constexpr int kFramePngLevel = 1;

struct Work {
  std::size_t frame = 0;
  double time = 0.0;
  double readMs = 0.0, buildMs = 0.0, sceneMs = 0.0, renderMs = 0.0, encodeMs = 0.0, writeMs = 0.0;
  std::size_t moved = 0, recomputed = 0, patches = 0;
  build::PatchList list;
  std::vector<glm::dvec3> centers;  // the frame's atoms, for a transparent frame (view::Frame)
  build::BallStickModel model;      // --ball-and-stick: the frame's (the topology's bonds)
  view::FrameBuffers image;
};

// Where the frames go, checked before any frame is read: the output folders exist (made if
// missing) and can be written; --mp4 has its PNGs, all the frames and ffmpeg.
struct Outputs {
  FramePattern png, exr;
  std::optional<fs::path> ffmpeg;
};

// ffmpeg chooses the container by the extension, after every frame is rendered: a name it
// cannot place is refused before the first frame.
void checkMovieName(const std::string& path) {
  std::string extension = fs::path(path).extension().string();
  for (char& c : extension) c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
  if (extension != ".mp4" && extension != ".m4v" && extension != ".mov" && extension != ".mkv")
    throw std::invalid_argument("--mp4 " + path + ": " +
                                (extension.empty() ? std::string("the name has no extension") : extension) +
                                " is no container for the H.264 movie ffmpeg makes; name it .mp4 (or .mov, .mkv)");
}

Outputs checkOutputs(const TrajectoryOptions& o, const Shard& shard) {
  if (o.output.empty() && o.exr.empty())
    throw std::invalid_argument("nothing to write: give -o frames/%05d.png and/or --exr frames/%05d.exr");
  Outputs out;
  out.png = o.output.empty() ? FramePattern() : FramePattern("-o", o.output);
  out.exr = o.exr.empty() ? FramePattern() : FramePattern("--exr", o.exr);
  if (!out.png.empty()) view::checkImageOutputName(out.png(0), "-o", view::ImageContent::Colour);
  if (!out.exr.empty()) view::checkImageOutputName(out.exr(0), "--exr", view::ImageContent::Buffers);
  if (build::isStandardOutput(o.mp4))
    throw std::invalid_argument("--mp4 " + o.mp4 + ": the movie cannot go to the standard output (an MP4 is "
                                "finished by seeking back to its start): give a file name");
  if (!o.mp4.empty()) checkMovieName(o.mp4);
  if (!out.png.empty()) build::prepareOutputPath(out.png(0), "-o");
  if (!out.exr.empty()) build::prepareOutputPath(out.exr(0), "--exr");
  if (!o.timings.empty()) build::prepareOutputPath(o.timings, "--timings");
  if (!o.mp4.empty()) build::prepareOutputPath(o.mp4, "--mp4");
  if (o.mp4.empty()) return out;
  if (o.output.empty()) throw std::invalid_argument("--mp4 is made from the PNG frames: give -o frames/%05d.png too");
  if (shard.count > 1)
    throw std::invalid_argument("--mp4 needs every frame, but this process renders a shard (" + shard.origin +
                                "): make the movie once all shards are done, e.g. with ffmpeg");
  out.ffmpeg = findOnPath("ffmpeg");
  if (!out.ffmpeg) throw std::invalid_argument("--mp4 needs ffmpeg on PATH (Debian: apt-get install ffmpeg)");
  return out;
}

// A pattern whose number names folders (f/%03d/x.png) has a folder for every frame: all of
// this process's are made and checked before any frame is read, as frame 0's was.
void prepareFrameFolders(const Outputs& out, const std::vector<std::size_t>& frames) {
  for (const auto& [pattern, option] : {std::pair{&out.png, "-o"}, std::pair{&out.exr, "--exr"}})
    if (!pattern->empty() && pattern->numbersFolders())
      for (std::size_t k : frames) build::prepareOutputPath((*pattern)(k), option);
}

// --flexible: the atoms that move (none given: all of them).
struct Flexible {
  std::vector<std::uint32_t> atoms;
  std::vector<char> isFlexible;  // per atom, when atoms is not empty
};

// A selection given but empty (`--flexible ""`, a shell variable left unset) selects no atom
// and is refused as any selection matching nothing is, not read as "all atoms move".
Flexible flexibleAtoms(const std::optional<std::string>& selection, const build::Molecule& reference) {
  Flexible f;
  if (!selection) return f;
  try {
    f.atoms = build::selectAtoms(reference, *selection);
  } catch (const std::invalid_argument& e) {
    throw std::invalid_argument("--flexible " + build::text::inQuotes(*selection) + " (atoms of " + reference.source +
                                "): " + e.what() +
                                (build::text::trim(*selection).empty()
                                     ? "; leave --flexible out to move every atom, or give the atoms that move, e.g. "
                                       "'resid 120-160'"
                                     : ""));
  }
  f.isFlexible.assign(reference.size(), 0);
  for (std::uint32_t i : f.atoms) f.isFlexible[i] = 1;
  return f;
}

// One camera for the whole run (stage "frame the camera"), written to --camera-out.
void frameTrajectory(ImageSetup& setup, const TrajectoryOptions& o, build::Trajectory& trajectory,
                     const std::vector<std::size_t>& frames, const build::Molecule& reference, const Flexible& flexible) {
  const build::SurfaceRequest request = o.surface.request();
  if (setup.framing.fixed && setup.framing.fixed->hasDepthRange()) {
    // --camera fixes the view and its depth range: no pass over the frames is needed.
    frameSpheres(setup, reference.centers, request.reach(reference.radii));
  } else if (o.frameCamera == "first") {
    const build::PatchList framing = request.builtKind() == build::SurfaceKind::Mss
                                         ? build::buildSurface(reference, request)
                                         : paramsOnly(request);
    frameSurface(setup, framing, reference);
  } else {
    const std::vector<double> reach = request.reach(reference.radii);
    frameSpheres(setup, frameEveryFrame(trajectory, o.trajectory, frames, reference, flexible.atoms, reach,
                                        framingOf(setup)));
  }
  writeCameraOut(setup);
}

// This process's frames, less those a finished earlier run wrote (--resume).
std::vector<std::size_t> framesToRender(const TrajectoryOptions& o, const std::vector<std::size_t>& mine,
                                        const Outputs& out, std::size_t& skipped) {
  std::vector<std::size_t> todo;
  skipped = 0;
  for (std::size_t k : mine) {
    const bool done =
        o.resume && complete(out.png.empty() ? "" : out.png(k)) && complete(out.exr.empty() ? "" : out.exr(k));
    if (done)
      ++skipped;
    else
      todo.push_back(k);
  }
  return todo;
}

// --timings: one row a frame, flushed as it is written, so that an interrupted run keeps the
// rows of the frames it finished; --resume appends to them.
class TimingsFile {
 public:
  TimingsFile(const std::string& path, bool resume) : path_(path) {
    if (path.empty()) return;
    std::error_code ec;
    const bool toStandardOutput = build::isStandardOutput(path);
    const bool append = !toStandardOutput && resume && fs::is_regular_file(path, ec) && fs::file_size(path, ec) > 0;
    if (toStandardOutput) {
      const int fd = ::dup(build::standardOutputDescriptor());
      file_.reset(fd < 0 ? nullptr : ::fdopen(fd, "w"));
      if (!file_ && fd >= 0) ::close(fd);
    } else {
      file_.reset(std::fopen(path.c_str(), append ? "a" : "w"));
    }
    if (!file_) throw build::OutputError("--timings " + path + ": cannot write the file: " + std::strerror(errno));
    if (!append &&
        (std::fputs("frame,time_ps,read_ms,build_ms,scene_ms,render_ms,encode_ms,write_ms,moved_atoms,"
                    "recomputed_atoms,patches\n",
                    file_.get()) < 0 ||
         std::fflush(file_.get()) != 0))
      failed();
  }
  void row(const Work& w) {
    if (!file_) return;
    if (std::fprintf(file_.get(), "%zu,%g,%g,%g,%g,%g,%g,%g,%zu,%zu,%zu\n", w.frame, w.time, w.readMs, w.buildMs,
                     w.sceneMs, w.renderMs, w.encodeMs, w.writeMs, w.moved, w.recomputed, w.patches) < 0 ||
        std::fflush(file_.get()) != 0)
      failed();
  }

 private:
  [[noreturn]] void failed() const {
    throw build::OutputError("--timings " + path_ + ": write failed: " + std::strerror(errno));
  }
  std::string path_;
  std::unique_ptr<std::FILE, int (*)(std::FILE*)> file_{nullptr, std::fclose};
};

// The frames of one process through the stages "read", "build or update", "render" (the
// scene, then the rays) and "encode and write": the build of frame k+1 beside the drawing of
// frame k and the writing of frames k-1, k-2, ..., which run in parallel (each frame's files
// are its own, so the order in which they land does not matter; the rows of --timings and the
// per-frame lines come in the order frames finish).
// The first error of any stage (a bad frame, a full disk) is kept and stops the input; the
// pipeline then drains, and the error is thrown once it has (an exception escaping a stage
// let the process exit while the build of the next frame still ran: a crash on a full disk).
class FrameLoop {
 public:
  FrameLoop(const TrajectoryOptions& o, build::Trajectory& trajectory, const build::Molecule& reference,
            const Flexible& flexible, const ImageSetup& setup, std::vector<glm::vec3> colors, const Outputs& out)
      : o_(o), trajectory_(trajectory), reference_(reference), flexible_(flexible), setup_(setup),
        colors_(std::move(colors)), out_(out), builder_(o.surface.request()), current_(reference),
        engine_(makeEngine(o.engine)), timings_(o.timings, o.resume),
        ballAndStick_(BallAndStick::of(o.image, reference)) {
    record_ = recordOf(o.surface, o.topology, o.image, o.commandLine);
    record_.trajectory = o.trajectory;
    ballAndStick_.describe(record_);
    describeColors(setup, record_);
  }

  void run(const std::vector<std::size_t>& todo);

  std::vector<double> readMs, buildMs, sceneMs, renderMs, encodeMs, writeMs;
  double rigidDrift = 0.0;  // how far atoms held rigid actually moved in the trajectory
  std::size_t written = 0;
  std::vector<std::size_t> writtenFrames;  // in the order they were written

 private:
  std::shared_ptr<Work> readAndBuild(std::size_t frame);
  void render(Work& w);
  void write(Work& w, ProgressBar& bar, std::size_t total);

  const TrajectoryOptions& o_;
  build::Trajectory& trajectory_;
  const build::Molecule& reference_;
  const Flexible& flexible_;
  const ImageSetup& setup_;
  const std::vector<glm::vec3> colors_;
  const Outputs& out_;
  build::SurfaceBuilder builder_;
  build::Molecule current_;
  bool built_ = false;
  const std::unique_ptr<view::Engine> engine_;
  bool described_ = false;  // record_ holds the engine's description (after the first frame)
  TimingsFile timings_;
  const BallAndStick ballAndStick_;  // bonds of the reference frame, once, for every frame
  ImageRecord record_;
  std::mutex finished_;  // the writers' shared records: timings, counts, the bar
};

std::shared_ptr<Work> FrameLoop::readAndBuild(std::size_t frame) {
  auto w = std::make_shared<Work>();
  w->frame = frame;
  auto t = std::chrono::steady_clock::now();
  trajectory_.load(w->frame);
  w->time = trajectory_.frame().time;
  const auto& c = trajectory_.molecule().centers;
  if (flexible_.atoms.empty()) {
    current_.centers = c;
  } else {
    for (std::uint32_t i : flexible_.atoms) current_.centers[i] = c[i];
    for (std::size_t i = 0; i < c.size(); ++i)
      if (!flexible_.isFlexible[i]) rigidDrift = std::max(rigidDrift, glm::length(c[i] - reference_.centers[i]));
  }
  w->readMs = millisecondsSince(t);
  t = std::chrono::steady_clock::now();
  if (!built_) {
    w->list = builder_.build(current_);
    built_ = true;
  } else {
    w->list = flexible_.atoms.empty() ? builder_.update(current_) : builder_.update(current_, flexible_.atoms);
  }
  w->buildMs = millisecondsSince(t);
  w->recomputed = builder_.lastRecomputed();
  w->patches = w->list.patchCount();
  w->moved = flexible_.atoms.empty() ? current_.size() : flexible_.atoms.size();
  if (setup_.render.opacity < 1.0) w->centers = current_.centers;  // the render stage runs beside the next read
  if (ballAndStick_.on) w->model = ballAndStick_.model(current_.centers, current_.radii);
  return w;
}

void FrameLoop::render(Work& w) {
  const auto t = std::chrono::steady_clock::now();
  // The atoms' radii do not change from frame to frame (the next frame's read changes the
  // centres alone, which w.centers copied).
  const std::span<const double> radii = w.centers.empty() ? std::span<const double>() : current_.radii;
  w.image = engine_->render({&w.list, w.centers, radii, colors_, &w.model, setup_.render});
  w.sceneMs = engine_->sceneSeconds() * 1e3;
  w.renderMs = millisecondsSince(t) - w.sceneMs;
  // The engine's description into every frame's record, once, after the first frame (GL's
  // context opens with it). This stage is serial and frame k is written only after this stage
  // has drawn it, so every write reads record_ after this, and no write runs beside it.
  if (!described_) {
    describeEngine(*engine_, record_);
    described_ = true;
  }
  w.list = build::PatchList();
}

void FrameLoop::write(Work& w, ProgressBar& bar, std::size_t total) {
  auto t = std::chrono::steady_clock::now();
  ImageRecord record = record_;
  record.frame = w.frame;
  record.timePs = w.time;
  const EncodedFiles files = encodeImage(out_.png.empty() ? "" : out_.png(w.frame),
                                         out_.exr.empty() ? "" : out_.exr(w.frame), w.image, record,
                                         setup_.render.camera, kFramePngLevel);
  w.image = view::FrameBuffers();
  w.encodeMs = millisecondsSince(t);
  t = std::chrono::steady_clock::now();
  writeFiles(files);
  w.writeMs = millisecondsSince(t);
  const std::lock_guard lock(finished_);
  readMs.push_back(w.readMs), buildMs.push_back(w.buildMs), sceneMs.push_back(w.sceneMs);
  renderMs.push_back(w.renderMs), encodeMs.push_back(w.encodeMs), writeMs.push_back(w.writeMs);
  timings_.row(w);
  writtenFrames.push_back(w.frame);
  // One line per frame when nobody watches a bar (the logs of batch jobs), flushed: a log in a
  // file is block-buffered, and a job killed at its time limit would lose every line.
  if (!o_.quiet && !isatty(STDERR_FILENO)) {
    std::printf("frame %zu: build %.1f ms, render %.1f ms\n", w.frame, w.buildMs, w.renderMs);
    std::fflush(stdout);
    build::checkStandardOutput();  // a log reader gone (| head) stops the run with the reason
  }
  bar.items(++written, total, "frames");
}

void FrameLoop::run(const std::vector<std::size_t>& todo) {
  ProgressBar bar(!o_.quiet, "frames");
  bar.items(0, todo.size(), "frames");
  std::size_t next = 0;
  std::exception_ptr failure;
  std::atomic<bool> failed{false};
  // Runs one stage; the first error is kept, and the stage's frame dropped.
  const auto guarded = [&](auto&& stage) {
    try {
      stage();
      return true;
    } catch (...) {
      if (!failed.exchange(true)) failure = std::current_exception();
      return false;
    }
  };
  using Item = std::shared_ptr<Work>;
  // Tokens: a frame building, one drawing, and two encoding (the encoders run in parallel).
  tbb::parallel_pipeline(
      4,
      tbb::make_filter<void, Item>(tbb::filter_mode::serial_in_order,
                                   [&](tbb::flow_control& fc) -> Item {
                                     Item w;
                                     if (next == todo.size() || failed.load() || InterruptHandler::signal() ||
                                         !guarded([&] { w = readAndBuild(todo[next++]); }))
                                       fc.stop();
                                     return w;
                                   }) &
          tbb::make_filter<Item, Item>(tbb::filter_mode::serial_in_order,
                                       [&](Item w) -> Item {
                                         if (!w || failed.load() || InterruptHandler::signal() ||
                                             !guarded([&] { render(*w); }))
                                           return nullptr;
                                         return w;
                                       }) &
          tbb::make_filter<Item, void>(tbb::filter_mode::parallel, [&](Item w) {
            if (w && !failed.load()) guarded([&] { write(*w, bar, todo.size()); });
          }));
  if (failure || InterruptHandler::signal()) bar.clear();
  if (failure) std::rethrow_exception(failure);
}

// ffmpeg's image sequences must be numbered without gaps: the frames are linked as 0, 1, 2, ...
void makeMovie(const TrajectoryOptions& o, const Outputs& out, const std::vector<std::size_t>& frames) {
  const fs::path links = fs::path(o.mp4).parent_path() / ("." + fs::path(o.mp4).filename().string() + ".frames");
  fs::remove_all(links);
  fs::create_directories(links);
  for (std::size_t i = 0; i < frames.size(); ++i) {
    char name[32];
    std::snprintf(name, sizeof name, "%08zu.png", i);
    fs::create_symlink(fs::absolute(out.png(frames[i])), links / name);
  }
  const int status = runProgram({out.ffmpeg->string(), "-y", "-loglevel", "error", "-framerate", std::to_string(o.fps),
                                 "-i", (links / "%08d.png").string(), "-vf", "pad=ceil(iw/2)*2:ceil(ih/2)*2", "-c:v",
                                 "libx264", "-pix_fmt", "yuv420p", o.mp4});
  fs::remove_all(links);
  if (status != 0) throw std::runtime_error("ffmpeg failed (exit " + std::to_string(status) + ") making " + o.mp4);
  std::printf("wrote %s (%zu frames at %g frames/s)\n", o.mp4.c_str(), frames.size(), o.fps);
}

void printPlan(const TrajectoryOptions& o, const build::Trajectory& trajectory, const build::Molecule& reference,
               std::size_t selected, std::size_t mine, const Shard& shard, std::size_t todo, std::size_t skipped,
               std::size_t flexible) {
  std::printf("%s + %s: %zu atoms (%zu in the file), %zu frames; %zu selected%s, %zu to render%s%s\n",
              o.topology.c_str(), o.trajectory.c_str(), reference.size(), reference.fileAtomCount,
              trajectory.frameCount(), selected,
              shard.count > 1 ? (", " + std::to_string(mine) + " in " + shard.origin).c_str() : "", todo,
              skipped ? (", " + std::to_string(skipped) + " done already (--resume)").c_str() : "",
              flexible == 0 ? "" : (", " + std::to_string(flexible) + " flexible atoms").c_str());
  std::fflush(stdout);
}

void printTimings(const FrameLoop& loop, double loopSeconds, double setupMs, double framingMs) {
  std::printf("rendered %zu frames in %.2f s (%.2f frames/s; setup %.0f ms, of which %.0f ms framing the camera); "
              "medians per frame: read %.2f ms, build %.2f ms, scene %.2f ms, render %.2f ms, encode %.2f ms, "
              "write %.2f ms\n",
              loop.written, loopSeconds, loopSeconds > 0 ? static_cast<double>(loop.written) / loopSeconds : 0.0,
              setupMs, framingMs, median(loop.readMs), median(loop.buildMs), median(loop.sceneMs),
              median(loop.renderMs), median(loop.encodeMs), median(loop.writeMs));
}

// The last line of an interrupted run: where it stopped and how to go on; then the process dies
// of `signal` (status 128 + signal in a shell: 130 for SIGINT, 143 for SIGTERM).
[[noreturn]] void stopInterrupted(int signal, const std::vector<std::size_t>& todo, std::vector<std::size_t> written) {
  std::sort(written.begin(), written.end());
  const char* name = signal == SIGINT ? "SIGINT" : "SIGTERM";
  const auto missing = std::find_if(todo.begin(), todo.end(),
                                    [&](std::size_t k) { return !std::binary_search(written.begin(), written.end(), k); });
  if (missing == todo.end())
    std::printf("interrupted by %s after the last frame: all %zu frames to render written\n", name, todo.size());
  else
    std::printf("interrupted by %s at frame %zu: %zu of the %zu frames to render written, %zu missing; resume with "
                "--resume (the same command with --resume renders only the missing frames)\n",
                name, *missing, written.size(), todo.size(), todo.size() - written.size());
  std::fflush(stdout);
  std::signal(signal, SIG_DFL);
  std::raise(signal);
  std::_Exit(128 + signal);  // not reached: the signal's default action ends the process
}

void runTrajectory(const TrajectoryOptions& o) {
  // Every option is checked before the slow work starts.
  const Shard shard = shardFromEnvironment(o.shard);
  const Outputs out = checkOutputs(o, shard);
  ImageSetup setup = resolveImageOptions(o.image);
  view::checkEngineCanDraw(o.engine, setup.render);
  const auto limit = limitThreads(o.threads);
  const auto start = std::chrono::steady_clock::now();
  build::Trajectory trajectory = readingFile(
      o.trajectory, "the trajectory", [&] { return build::Trajectory(o.topology, o.trajectory, o.read); });
  for (const std::string& note : trajectory.source().notes())
    std::fprintf(stderr, "surftrace: note: %s: %s\n", o.trajectory.c_str(), note.c_str());
  const std::vector<std::size_t> frames = selectFrames(o.frames, trajectory.frameCount());
  const std::vector<std::size_t> mine = framesOfShard(frames, shard);
  prepareFrameFolders(out, mine);
  // The reference frame: the first one selected, whichever shard this is, so that every shard
  // has the same camera and the same rigid atoms.
  trajectory.load(frames.front());
  const build::Molecule reference = trajectory.molecule();
  printReadNotes(reference);
  const Flexible flexible = flexibleAtoms(o.flexible, reference);
  if (mine.empty()) {
    std::printf("%s: no frames to render: %zu frames are selected, and this shard renders those at positions %zu, "
                "%zu, ... of them (the selected frame at position i, counted from 0, goes to shard i mod %zu)\n",
                shard.origin.c_str(), frames.size(), shard.index, shard.index + shard.count, shard.count);
    return;
  }
  const auto framingStart = std::chrono::steady_clock::now();
  frameTrajectory(setup, o, trajectory, frames, reference, flexible);
  const double framingMs = millisecondsSince(framingStart);
  std::size_t skipped = 0;
  const std::vector<std::size_t> todo = framesToRender(o, mine, out, skipped);
  const double setupMs = millisecondsSince(start);
  printPlan(o, trajectory, reference, frames.size(), mine.size(), shard, todo.size(), skipped, flexible.atoms.size());

  std::vector<glm::vec3> colors = colorAtoms(setup, reference);
  writeLegendFile(setup);
  FrameLoop loop(o, trajectory, reference, flexible, setup, std::move(colors), out);
  const auto loopStart = std::chrono::steady_clock::now();
  // From the first frame on (before it, a signal ends the process as it always does: there is
  // nothing to keep).
  const InterruptHandler interrupts;
  loop.run(todo);
  if (const int signal = InterruptHandler::signal()) stopInterrupted(signal, todo, loop.writtenFrames);
  printTimings(loop, millisecondsSince(loopStart) * 1e-3, setupMs, framingMs);
  if (!flexible.atoms.empty())
    std::printf("atoms outside --flexible were held at frame %zu; in the trajectory they moved up to %.3f Å\n",
                frames.front(), loop.rigidDrift);
  if (!out.png.empty() && !todo.empty())
    std::printf("wrote %s ... %s\n", out.png(todo.front()).c_str(), out.png(todo.back()).c_str());
  if (!out.exr.empty() && !todo.empty())
    std::printf("wrote %s ... %s\n", out.exr(todo.front()).c_str(), out.exr(todo.back()).c_str());
  if (out.ffmpeg) makeMovie(o, out, frames);
}

}  // namespace

constexpr const char* kTrajectoryExamples =
      "Frames are numbered from 0 (as in MDAnalysis and VMD): -o f/%05d.png writes frame 7 to f/00007.png.\n"
      "Examples:\n"
      "  surftrace trajectory adk.psf adk_dims.dcd -o frames/%05d.png --size 512x512\n"
      "  surftrace trajectory adk.psf adk_dims.dcd --frames 0:98:4 --surface mss --shrink 0.5 -o f/%03d.png --mp4 adk.mp4\n"
      "  surftrace trajectory top.gro traj.xtc --flexible 'resid 120-160' -o f/%05d.png --timings t.csv\n"
      "  sbatch --array=0-3 ...  (task t renders the i-th selected frame when i mod 4 = t; see the README)";

void addTrajectoryCommand(CLI::App& app, const std::string& commandLine) {
  auto o = std::make_shared<TrajectoryOptions>();
  o->commandLine = commandLine;
  auto* cmd = app.add_subcommand(
      "trajectory",
      "Ray-trace a molecular surface frame after frame from a molecular-dynamics trajectory (one camera for the whole "
      "run, partial updates for --flexible atoms, frames shared out with --shard or a Slurm job array)");
  cmd->footer(kTrajectoryExamples);
  cmd->add_option("TOPOLOGY", o->topology,
                  "The atoms: PSF (CHARMM/NAMD), GRO, PDB or mmCIF (gzipped allowed), in the trajectory's atom order")
      ->required()
      ->check(CLI::ExistingFile);
  cmd->add_option("TRAJECTORY", o->trajectory,
                  "The coordinates per frame: DCD (CHARMM/NAMD), XTC (GROMACS), GRO or XYZ frames one after another, "
                  "or a multi-model PDB/mmCIF")
      ->required()
      ->check(CLI::ExistingFile);
  addSurfaceOptions(*cmd, o->surface);
  cmd->add_option("-o,--output", o->output,
                  "PNG file name pattern with one integer conversion for the frame number, e.g. frames/%05d.png "
                  "(folders are made as needed); each PNG holds the sRGB encoding of the linear colour the --exr "
                  "frames hold");
  cmd->add_option("--exr", o->exr, "EXR pattern (colour, depth, normal, ids, flags per frame), e.g. frames/%05d.exr");
  cmd->add_option("--frames", o->frames,
                  "Frames a:b:step: a, a+step, ... below b, numbered from 0 (default: all); a single number is one "
                  "frame");
  cmd->add_option("--frame-camera", o->frameCamera,
                  "all: every selected frame whole in view, centred on their union and framed as `render` frames "
                  "one structure (one parallel pass over the coordinates; every shard computes the same camera); "
                  "first: the first selected frame only. Either way the camera stays fixed for the whole run, so a "
                  "movie does not jitter")
      ->check(CLI::IsMember({"all", "first"}))
      ->default_val("all");
  CLI::Option* flexible = cmd->add_option("--flexible", o->flexible,
                  "Only these atoms move (the rest stay where the first selected frame has them) and each frame is "
                  "a partial update. MDAnalysis's selection language: name, resname, resid, chain, segid, element, "
                  "index (from 0), atom (from 1; MDAnalysis's bynum), protein, backbone, water, all; several values "
                  "(resid 10-20 45, name CA CB, name H*); combined with not, then and/or left to right, and "
                  "parentheses, e.g. 'resname R2M and name Ru1' or 'protein and (resid 120-160 or chain B)'; commas "
                  "join whole selections (their union)");
  cmd->add_flag("--resume", o->resume,
                "Skip the frames whose output files exist (files are written whole, through a temporary name, so an "
                "interrupted run leaves none half-written)");
  cmd->add_option("--timings", o->timings,
                  "Write per-frame timings to this CSV, in ms: read, build (or update), scene (Embree's BVH), render "
                  "(the rays and the image effects), encode (PNG, EXR), write; - for the standard output (the other "
                  "lines then go to the standard error)");
  cmd->add_option("--mp4", o->mp4, "Also make an H.264 movie of the PNG frames with ffmpeg (must be on PATH)");
  cmd->add_option("--fps", o->fps, "Frames per second of the --mp4 movie")->check(positive())->default_val(25.0);
  cmd->add_option("--shard", o->shard,
                  "i/n (0 <= i < n): render only the i-th, (i+n)-th, (i+2n)-th, ... of the selected frames (counted "
                  "from 0 in --frames order), so that n shards write each selected frame once. Without it, a Slurm "
                  "array task's SLURM_ARRAY_TASK_ID and SLURM_ARRAY_TASK_COUNT choose the shard");
  addImageOptions(*cmd, o->image);
  addEngineOptions(*cmd, o->engine);
  cmd->add_option("--threads", o->threads, "Worker threads (default: all cores); images do not depend on it")
      ->check(wholeIn(0, 4096));
  cmd->add_flag("--quiet", o->quiet, "No progress bar and no per-frame lines");
  addMoleculeOptions(*cmd, o->read);
  cmd->callback([o, flexible] {
    if (flexible->count() > 0 && !o->flexible) o->flexible.emplace();  // `--flexible ""`: given, empty
    runTrajectory(*o);
  });
}

}  // namespace surftrace::tools
