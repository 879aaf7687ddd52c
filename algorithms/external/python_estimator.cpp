// Python.h first (it sets feature macros the C library's headers read).
#if GRAPEBENCH_WITH_PYTHON
#include <pybind11/embed.h>
#include <pybind11/numpy.h>
#include <pybind11/stl.h>
#endif

#include "algorithms/external/python_estimator.h"

#include <algorithm>
#include <atomic>
#include <chrono>
#include <cstdlib>
#include <filesystem>
#include <mutex>
#include <new>
#include <optional>
#include <thread>
#include <utility>

#include "synth/config.h"
#include "synth/run_stop.h"

namespace grapebench {

const ParamTable<PythonParams>& python_param_table() {
  using P = PythonParams;
  static const ParamTable<P> table =
      ParamTable<P>()
          .string("module", &P::module, "the Python module, imported by name (my_estimator for my_estimator.py)")
          .required()
          .string("function", &P::function, "called as function(request) -> answer (algorithms/external/python_estimator.h)")
          .strings("path", &P::path, 0, "folders put first on sys.path (\"{scene_dir}\": the scene file's folder)")
          .choice("input", &P::input,
                  {{"cloud", ExternalParams::Input::Cloud},
                   {"stereo_pair", ExternalParams::Input::StereoPair},
                   {"labelled_cloud", ExternalParams::Input::LabelledCloud},
                   {"image", ExternalParams::Input::Image}},
                  "what it measures, as the external protocol's version 2: cloud, stereo_pair, labelled_cloud "
                  "(class_scores answer) or image (instances answer)")
          .choice_list("quantities", &P::quantities, quantity_choices(), 1, "what the answer holds")
          .when("input: cloud or stereo_pair",
                [](const P& p) {
                  return p.input == ExternalParams::Input::Cloud || p.input == ExternalParams::Input::StereoPair;
                })
          .document("params", &P::params, "handed to the function as request[\"params\"] (its own settings)");
  return table;
}

namespace {

// The protocol's rules for the answer, with the function named in messages.
ExternalParams answer_rules(const PythonParams& p) {
  ExternalParams x;
  x.version = 2;
  x.input = p.input;
  x.quantities = p.quantities;
  x.who = "python estimator '" + p.module + "." + p.function + "'";
  return x;
}

}  // namespace

#if GRAPEBENCH_WITH_PYTHON

namespace py = pybind11;

// Initialized and not finalizing (Python 3.13 made _Py_IsFinalizing public as Py_IsFinalizing).
bool interpreter_running() {
#if PY_VERSION_HEX >= 0x030D0000
  return Py_IsInitialized() && !Py_IsFinalizing();
#else
  return Py_IsInitialized() && !_Py_IsFinalizing();
#endif
}

// A strong reference (a plain PyObject*: pybind11's types have hidden visibility).
class PythonFunction {
 public:
  explicit PythonFunction(const py::object& f) : f_(f.inc_ref().ptr()) {}
  // Released under the GIL; left to the process's end once the interpreter is
  // finalizing (a scene collected at Python's exit).
  ~PythonFunction() {
    if (interpreter_running()) {
      py::gil_scoped_acquire gil;
      Py_DECREF(f_);
    }
  }
  PythonFunction(const PythonFunction&) = delete;
  PythonFunction& operator=(const PythonFunction&) = delete;
  py::handle get() const { return f_; }

 private:
  PyObject* f_;
};

namespace {

// The command line has no interpreter: start one, once, and hand its GIL back (each
// call takes it). Inside `import grapebench` the caller's interpreter is used as is.
void ensure_interpreter() {
  static std::once_flag once;
  std::call_once(once, [] {
    if (Py_IsInitialized()) return;
    // No Python signal handlers (Ctrl-C stays the harness's), no '' (the working
    // folder) on sys.path: a module comes from its entry's `path` or the system.
    py::initialize_interpreter(false, 0, nullptr, false);
    if (const char* venv = std::getenv("VIRTUAL_ENV"); venv && *venv) {
      // An active venv's packages first, as its own python would see them.
      py::exec(
          "import os, site, sys\n"
          "d = f'{venv}/lib/python{sys.version_info[0]}.{sys.version_info[1]}/site-packages'\n"
          "if os.path.isdir(d):\n"
          "    site.addsitedir(d)\n"
          "    sys.path.remove(d)\n"
          "    sys.path.insert(0, d)\n"
          "else:\n"
          "    sys.stderr.write(f'grapebench: VIRTUAL_ENV {venv} has no {d}: its packages are not seen\\n')\n",
          py::globals(), py::dict(py::arg("venv") = venv));
    }
    PyEval_SaveThread();
  });
}

// The exception being handled, as its traceback's last lines.
std::string traceback_tail(py::error_already_set& e) {
  std::string text;
  try {
    const py::object lines = py::module_::import("traceback").attr("format_exception")(e.type(), e.value(), e.trace());
    text = py::str("").attr("join")(lines).cast<std::string>();
  } catch (const std::exception&) {
    text = e.what();
  }
  while (!text.empty() && text.back() == '\n') text.pop_back();
  constexpr std::size_t kTail = 800;
  return text.size() > kTail ? "..." + text.substr(text.size() - kTail) : text;
}

// What the function printed, out now: the command's interpreter is never finalized,
// so Python's buffers would not be flushed at exit.
void flush_output() {
  const py::module_ sys = py::module_::import("sys");
  for (const char* stream : {"stdout", "stderr"}) {
    const py::object s = sys.attr(stream);
    if (!s.is_none()) s.attr("flush")();
  }
}

// The request's arrays are copies (the function may keep them), in memory reused from
// call to call: fresh memory for a 30 000-point cloud's three arrays page-faulted on
// every call, 5.1 ms of the 5.1 ms a call took (perf, bench/perf/python_perf.cpp).
// A block returns here when its array dies, whenever that is.
class BlockPool {
 public:
  // A block of at least `bytes`; `bytes` becomes its real size.
  void* take(std::size_t& bytes) {
    {
      const std::lock_guard<std::mutex> lock(m_);
      for (auto it = free_.begin(); it != free_.end(); ++it) {
        if (it->second >= bytes && it->second <= 2 * bytes + 4096) {
          void* p = it->first;
          bytes = it->second;
          kept_ -= it->second;
          free_.erase(it);
          return p;
        }
      }
    }
    void* p = std::malloc(bytes);
    if (!p) throw std::bad_alloc();
    return p;
  }
  void give(void* p, std::size_t bytes) {
    const std::lock_guard<std::mutex> lock(m_);
    if (free_.size() < kMaxBlocks && kept_ + bytes <= kMaxBytes) {
      free_.emplace_back(p, bytes);
      kept_ += bytes;
    } else {
      std::free(p);
    }
  }

 private:
  static constexpr std::size_t kMaxBlocks = 64, kMaxBytes = std::size_t{512} << 20;
  std::mutex m_;
  std::vector<std::pair<void*, std::size_t>> free_;
  std::size_t kept_ = 0;
};

BlockPool& block_pool() {
  static BlockPool* pool = new BlockPool;  // never destroyed: arrays may die at Python's exit
  return *pool;
}

template <class T>
py::array_t<T> pooled(std::vector<py::ssize_t> shape) {
  std::size_t n = 1;
  for (const py::ssize_t d : shape) n *= static_cast<std::size_t>(d);
  struct Block {
    void* p;
    std::size_t bytes;
  };
  std::size_t bytes = std::max<std::size_t>(n * sizeof(T), 1);
  void* p = block_pool().take(bytes);
  auto* b = new Block{p, bytes};
  const py::capsule owner(b, [](void* x) {
    auto* blk = static_cast<Block*>(x);
    block_pool().give(blk->p, blk->bytes);
    delete blk;
  });
  return py::array_t<T>(std::move(shape), static_cast<T*>(b->p), owner);
}

py::array_t<double> rows_of(const PointCloud& c) {
  py::array_t<double> a = pooled<double>({static_cast<py::ssize_t>(c.rows()), 3});
  auto m = a.mutable_unchecked<2>();
  for (Eigen::Index i = 0; i < c.rows(); ++i)
    for (int j = 0; j < 3; ++j) m(i, j) = c(i, j);
  return a;
}

py::object image_of(const RgbImage& im) {
  if (im.data.empty()) return py::none();
  if (im.data.size() != static_cast<std::size_t>(im.width) * static_cast<std::size_t>(im.height) * 3)
    throw std::logic_error("python estimator: an image's data is not width x height x 3 bytes");
  py::array_t<std::uint8_t> a = pooled<std::uint8_t>({im.height, im.width, 3});
  std::copy(im.data.begin(), im.data.end(), a.mutable_data());
  return a;
}

// The request of algorithms/external/python_estimator.h: the external protocol's version 2
// with arrays where it names files.
py::dict request_of(const EstimatorInput& in, const PythonParams& p) {
  const auto n = in.points.rows();
  const bool normals = in.normals.rows() == n && n > 0, viewpoints = in.viewpoints.rows() == n && n > 0;
  const bool colours = static_cast<Eigen::Index>(in.colours.size()) == n && n > 0;
  py::dict r;
  r["protocol"] = "grapebench-estimator-2";
  const bool image = p.input == ExternalParams::Input::Image;
  r["kind"] = image                     ? "image"
              : in.stereo               ? "stereo_pair"
              : !in.train_labels.empty() ? "classification"
              : in.frame                ? "single_frame"
              : !in.views.empty()       ? "multi_view"
                                        : "cloud";
  r["cloud"] = rows_of(in.points);
  r["points"] = n;
  r["units"] = "m";
  py::list quantities;
  for (Quantity q : p.quantities) quantities.append(quantity_name(q));
  r["quantities"] = quantities;
  // A fresh dict per call: a function that edits its params cannot change the next case.
  r["params"] = py::module_::import("json").attr("loads")(p.params.dump());
  py::list attributes;
  if (normals) {
    attributes.append("normals");
    r["normals"] = rows_of(in.normals);
  }
  if (viewpoints) {
    attributes.append("viewpoints");
    r["viewpoints"] = rows_of(in.viewpoints);
  }
  if (colours) {
    attributes.append("colours");
    py::array_t<std::uint8_t> c = pooled<std::uint8_t>({n, 3});
    auto m = c.mutable_unchecked<2>();
    for (Eigen::Index i = 0; i < n; ++i) {
      const Rgb8& x = in.colours[static_cast<std::size_t>(i)];
      m(i, 0) = x[0], m(i, 1) = x[1], m(i, 2) = x[2];
    }
    r["colours"] = c;
  }
  r["attributes"] = attributes;
  py::list views;
  for (const InputView& v : in.views) {
    py::array_t<double> pose(std::vector<py::ssize_t>{4, 4});
    auto m = pose.mutable_unchecked<2>();
    const Eigen::Matrix4d t = v.pose.matrix();
    for (int a = 0; a < 4; ++a)
      for (int b = 0; b < 4; ++b) m(a, b) = t(a, b);
    py::dict d;
    d["name"] = v.name;
    d["pose"] = pose;
    d["cloud"] = rows_of(v.points);
    d["points"] = v.points.rows();
    views.append(d);
  }
  r["views"] = views;
  if (!in.train_labels.empty()) {
    r["classes"] = in.classes;
    py::array_t<std::int64_t> labels = pooled<std::int64_t>({static_cast<py::ssize_t>(in.train_labels.size())});
    std::copy(in.train_labels.begin(), in.train_labels.end(), labels.mutable_data());
    r["train_labels"] = labels;
  }
  if (in.stereo) {
    const StereoPair& s = *in.stereo;
    py::dict d;
    d["left"] = image_of(s.left);
    d["right"] = image_of(s.right);
    d["width"] = s.left.width;
    d["height"] = s.left.height;
    d["fx"] = s.fx, d["fy"] = s.fy, d["cx"] = s.cx, d["cy"] = s.cy;
    d["baseline"] = s.baseline;
    r[image ? "image" : "stereo"] = d;
    return r;
  }
  if (in.frame) {
    const InputFrame& f = *in.frame;
    py::dict d;
    d["index"] = f.index, d["roi"] = f.roi, d["region"] = f.region, d["width"] = f.width, d["height"] = f.height;
    d["fx"] = f.fx, d["fy"] = f.fy, d["cx"] = f.cx, d["cy"] = f.cy;
    r["frame"] = d;
  }
  return r;
}

// The answer as JSON: dicts, lists, tuples, str, bool, int, float, None, and anything
// with tolist() (numpy arrays and scalars).
nlohmann::json answer_json(const py::handle& h, const ExternalParams& rules, int depth = 0) {
  if (depth > 64) throw InputError(rules.who + ": the answer is nested deeper than 64 levels");
  if (h.is_none()) return nullptr;
  if (py::isinstance<py::bool_>(h)) return h.cast<bool>();
  if (py::isinstance<py::int_>(h)) {
    try {
      return h.cast<std::int64_t>();
    } catch (const py::cast_error&) {
      return h.cast<double>();
    }
  }
  if (py::isinstance<py::float_>(h)) return h.cast<double>();
  if (py::isinstance<py::str>(h)) return h.cast<std::string>();
  if (py::isinstance<py::dict>(h)) {
    nlohmann::json o = nlohmann::json::object();
    for (const auto& [k, v] : h.cast<py::dict>()) {
      if (!py::isinstance<py::str>(k)) throw InputError(rules.who + ": the answer's keys must be strings");
      o[k.cast<std::string>()] = answer_json(v, rules, depth + 1);
    }
    return o;
  }
  if (py::isinstance<py::list>(h) || py::isinstance<py::tuple>(h)) {
    nlohmann::json a = nlohmann::json::array();
    for (const auto& v : h) a.push_back(answer_json(v, rules, depth + 1));
    return a;
  }
  if (py::hasattr(h, "tolist")) return answer_json(h.attr("tolist")(), rules, depth + 1);
  throw InputError(rules.who + ": the answer holds a " + py::str(py::type::of(h).attr("__name__")).cast<std::string>() +
                   ", not a JSON value (dict, list, str, number, bool, None or a numpy array)");
}

// The run's time budget for Python code, which never polls the stop flag: a thread of
// the process looks every 20 ms at the calls in progress and, when a call's run has
// been told to stop, raises TimeoutError in its thread (PyThreadState_SetAsyncExc; it
// fires at the function's next bytecode, not inside a long C call). A call registers
// and leaves while holding the GIL, and the watcher raises only while holding it, so
// the exception never reaches a thread that has left its call.
class Stopper {
 public:
  static Stopper& instance() {
    static Stopper* s = new Stopper;  // its thread outlives static destruction
    return *s;
  }
  struct Call {
    unsigned long ident;
    const std::atomic<bool>* stop;
    bool raised = false;
  };
  void enter(Call* c) {
    const std::lock_guard<std::mutex> lock(m_);
    calls_.push_back(c);
    if (!started_) {
      started_ = true;
      std::thread([this] { watch(); }).detach();
    }
  }
  void leave(Call* c) {
    const std::lock_guard<std::mutex> lock(m_);
    calls_.erase(std::find(calls_.begin(), calls_.end(), c));
  }

 private:
  bool any_due() {
    const std::lock_guard<std::mutex> lock(m_);
    for (const Call* c : calls_)
      if (!c->raised && c->stop->load(std::memory_order_relaxed)) return true;
    return false;
  }
  void watch() {
    for (;;) {
      std::this_thread::sleep_for(std::chrono::milliseconds(20));
      if (!any_due() || !interpreter_running()) continue;
      py::gil_scoped_acquire gil;
      const std::lock_guard<std::mutex> lock(m_);
      for (Call* c : calls_) {
        if (c->raised || !c->stop->load(std::memory_order_relaxed)) continue;
        PyThreadState_SetAsyncExc(c->ident, PyExc_TimeoutError);
        c->raised = true;
      }
    }
  }
  std::mutex m_;
  std::vector<Call*> calls_;
  bool started_ = false;
};

// Registers this thread's call (GIL held) when its run has a stop flag.
class StopWatch {
 public:
  StopWatch() {
    if (!tls_run_stop) return;
    call_ = Stopper::Call{PyThread_get_thread_ident(), tls_run_stop};
    Stopper::instance().enter(&*call_);
  }
  ~StopWatch() {
    if (!call_) return;
    Stopper::instance().leave(&*call_);
    if (call_->raised) PyThreadState_SetAsyncExc(call_->ident, nullptr);  // not fired yet: cleared
  }
  StopWatch(const StopWatch&) = delete;
  StopWatch& operator=(const StopWatch&) = delete;
  bool stopped() const { return call_ && call_->stop->load(); }

 private:
  std::optional<Stopper::Call> call_;
};

}  // namespace

bool python_available() { return true; }

std::shared_ptr<PythonFunction> load_python_function(const PythonParams& p) {
  ensure_interpreter();
  py::gil_scoped_acquire gil;
  try {
    // What the harness itself imports, before a scene folder can shadow it (a json.py).
    py::module_::import("json");
    py::module_::import("traceback");
    py::list sys_path = py::module_::import("sys").attr("path");
    for (auto it = p.path.rbegin(); it != p.path.rend(); ++it) {
      if (!sys_path.contains(*it)) sys_path.insert(0, *it);
    }
    const py::module_ m = py::module_::import(p.module.c_str());
    // Python keeps one module per name: a second scene folder's my_estimator.py would
    // silently run the first one's. Where the entry's path holds the module, it must be
    // the one imported.
    std::string relative = p.module;
    std::replace(relative.begin(), relative.end(), '.', '/');
    for (const std::string& folder : p.path) {
      std::filesystem::path want;
      for (const auto& c : {std::filesystem::path(folder) / (relative + ".py"),
                            std::filesystem::path(folder) / relative / "__init__.py"}) {
        std::error_code ec;
        if (std::filesystem::is_regular_file(c, ec)) want = std::filesystem::weakly_canonical(c, ec);
        if (!want.empty()) break;
      }
      if (want.empty()) continue;
      const py::object file = py::getattr(m, "__file__", py::none());
      std::error_code ec;
      const std::filesystem::path got =
          file.is_none() ? std::filesystem::path() : std::filesystem::weakly_canonical(file.cast<std::string>(), ec);
      if (got != want)
        throw InputError("python estimator: module '" + p.module + "' is already imported from " +
                         (got.empty() ? std::string("(no file)") : got.string()) + ", not " + want.string() +
                         " (one module per name in a process: rename one of them)");
      break;
    }
    if (!py::hasattr(m, p.function.c_str()))
      throw InputError("python estimator: module '" + p.module + "' (" +
                       py::str(m.attr("__file__")).cast<std::string>() + ") has no '" + p.function + "'");
    py::object f = m.attr(p.function.c_str());
    if (!PyCallable_Check(f.ptr()))
      throw InputError("python estimator: '" + p.module + "." + p.function + "' is not callable");
    return std::make_shared<PythonFunction>(f);
  } catch (py::error_already_set& e) {
    throw InputError("python estimator: importing '" + p.module + "' failed: " + traceback_tail(e));
  }
}

Estimate python_estimate(const EstimatorInput& input, const PythonParams& p) {
  const ExternalParams rules = answer_rules(p);
  require_external_input(input, rules);
  if (!p.callable) throw std::logic_error("python estimator: called before its function was loaded");
  nlohmann::json answer;
  {
    py::gil_scoped_acquire gil;
    StopWatch watch;  // the run's time budget raises TimeoutError in the function
    try {
      const py::object a = p.callable->get()(request_of(input, p));
      answer = answer_json(a, rules);
      flush_output();
    } catch (py::error_already_set& e) {
      if (watch.stopped()) throw StopRequested();
      throw InputError(rules.who + ": raised " + traceback_tail(e));
    } catch (const py::cast_error& e) {  // an int past a double, text that is not UTF-8
      throw InputError(rules.who + ": the answer holds a value JSON cannot carry: " + e.what());
    } catch (...) {
      // Past a budget operator new fails (bench/heap_meter.h), so pybind11 cannot even
      // wrap the TimeoutError: a bad_alloc comes instead. The Python error is dropped;
      // the row says which budget it passed.
      PyErr_Clear();
      throw;
    }
  }
  const int width = input.stereo ? input.stereo->left.width : 0, height = input.stereo ? input.stereo->left.height : 0;
  return require_class_scores(parse_external_answer(answer, rules, input.points.rows(), width, height), input, rules);
}

#else  // built without Python

class PythonFunction {};

bool python_available() { return false; }

std::shared_ptr<PythonFunction> load_python_function(const PythonParams&) {
  throw InputError("python estimator: this build has no Python (configure with -DGRAPEBENCH_BUILD_PYTHON=ON; "
                   "Debian's pybind11-dev and python3-dev)");
}

Estimate python_estimate(const EstimatorInput&, const PythonParams& p) {
  throw InputError(answer_rules(p).who + ": this build has no Python");
}

#endif

}  // namespace grapebench
