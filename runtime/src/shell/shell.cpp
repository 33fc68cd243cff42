#include "shell/shell.h"

#include <fmt/format.h>
#include <readline/history.h>
#include <readline/readline.h>
#include <yaml-cpp/yaml.h>

#include <cmath>
#include <cstdlib>
#include <cstring>
#include <iostream>
#include <sstream>

#include "commands/introspection.h"
#include "plugslam/errors.h"
#include "plugslam/registry.h"
#include "shell/module_paths.h"

namespace plugslam::runtime {

namespace {

struct CommandHelp {
  const char* name;
  const char* usage;
  const char* doc;
};

const CommandHelp kCommands[] = {
    {"load", "load CONFIG", "read a config and build its modules"},
    {"validate", "validate", "check the current config (plugins, types, keys, values)"},
    {"run", "run", "run the pipeline on a worker thread (see pause, status, stop)"},
    {"pause", "pause", "pause the run after the current frame"},
    {"resume", "resume", "continue a paused run"},
    {"step", "step N", "process N frames (starting a run if none), then pause"},
    {"stop", "stop", "end the run now; outputs and run.json are written"},
    {"wait", "wait", "wait until the run pauses or ends"},
    {"status", "status", "frame, rate, local maps, graph size, loops closed"},
    {"rate", "rate [R]", "show or set the playback rate: 0 = as fast as possible, 1 = the data's "
     "own speed (by its timestamps), 2 = twice as fast"},
    {"set", "set PATH VALUE", "change a parameter (checked like the YAML) and rebuild"},
    {"get", "get PATH", "show a parameter or a module by pipeline path"},
    {"list", "list actions", "every module action, by module path"},
    {"do", "do MODULE.ACTION [ARGS]", "run a module action (e.g. pipeline.graph.optimize_now)"},
    {"plugins", "plugins", "the loaded plugins"},
    {"reload", "reload PLUGIN", "unload a plugin and load its file again (a rebuilt .so)"},
    {"swap", "swap PATH TYPE", "replace the module at PATH by one of another type"},
    {"save", "save DIR", "save a session: config, maps, graph, trajectory"},
    {"load-session", "load-session DIR [--localize]",
     "load a session: the next run extends it, or localizes in it (--localize)"},
    {"help", "help", "this list"},
    {"quit", "quit", "leave (a run in progress is stopped)"},
};

std::vector<std::string> tokenize(const std::string& line) {
  std::vector<std::string> out;
  std::istringstream in(line);
  std::string t;
  while (in >> t) out.push_back(t);
  return out;
}

std::string oneLine(std::string s) {
  for (char& c : s)
    if (c == '\n') c = ' ';
  return s;
}

std::string trim(const std::string& s) {
  const auto b = s.find_first_not_of(" \t\r");
  if (b == std::string::npos) return "";
  return s.substr(b, s.find_last_not_of(" \t\r") - b + 1);
}

const char* stateName(int s) {
  static const char* names[] = {"idle", "running", "paused", "finished"};
  return names[s];
}

int64_t parseCount(const std::string& s) {
  if (s.empty() || s.find_first_not_of("0123456789") != std::string::npos || s.size() > 12)
    throw InputError("expected a positive number of frames, got '" + s + "'");
  int64_t n = std::stoll(s);
  if (n <= 0) throw InputError("expected a positive number of frames, got '" + s + "'");
  return n;
}

}  // namespace

const std::vector<std::string>& Shell::commandNames() {
  static const std::vector<std::string> names = [] {
    std::vector<std::string> v;
    for (const auto& c : kCommands) v.push_back(c.name);
    v.push_back("exit");
    return v;
  }();
  return names;
}

Shell::Shell(std::ostream& out, ShellOptions options) : out_(&out), options_(std::move(options)) {}

Shell::~Shell() {
  if (worker_.joinable()) {
    {
      auto lk = lockBetweenFrames();
      stop_requested_ = true;
    }
    cv_.notify_all();
    worker_.join();
  }
  exec_.reset();
  run_.reset();
  session_.reset();
}

bool Shell::execute(const std::string& raw) {
  std::lock_guard<std::recursive_mutex> lock(command_mutex_);
  return executeLocked(raw);
}

std::string Shell::capture(const std::string& line, bool& ok) {
  std::lock_guard<std::recursive_mutex> lock(command_mutex_);
  std::ostringstream buffer;
  std::ostream* terminal = out_;
  const bool echo = options_.echo;
  const int errors = errors_;
  out_ = &buffer;
  options_.echo = false;
  try {
    executeLocked(line);
  } catch (...) {
    out_ = terminal;
    options_.echo = echo;
    throw;
  }
  out_ = terminal;
  options_.echo = echo;
  ok = errors_ == errors;
  std::string text = buffer.str();
  while (!text.empty() && text.back() == '\n') text.pop_back();
  return text;
}

bool Shell::executeLocked(const std::string& raw) {
  const std::string line = trim(raw);
  if (line.empty() || line[0] == '#') return true;
  if (options_.echo) *out_ << "> " << line << "\n";
  const auto args_all = tokenize(line);
  const std::string cmd = args_all[0];
  const Args args(args_all.begin() + 1, args_all.end());
  const std::string rest = trim(line.substr(cmd.size()));
  if (cmd == "quit" || cmd == "exit") {
    if (worker_.joinable()) cmdStop();
    return false;
  }
  try {
    reportWorkerError();
    dispatch(cmd, args, rest);
  } catch (const std::exception& e) {
    ++errors_;
    // A config with several errors lists them one a line; each line reads as an error.
    std::istringstream lines(e.what());
    for (std::string l; std::getline(lines, l);) *out_ << "error: " << l << "\n";
  }
  out_->flush();
  return true;
}

void Shell::dispatch(const std::string& cmd, const Args& a, const std::string& rest) {
  auto want = [&](size_t n, const char* usage) {
    if (a.size() != n) throw InputError(std::string("usage: ") + usage);
  };
  if (cmd == "load") return want(1, "load CONFIG"), cmdLoad(a);
  if (cmd == "validate") return want(0, "validate"), cmdValidate();
  if (cmd == "run") return want(0, "run"), cmdRun();
  if (cmd == "pause") return want(0, "pause"), cmdPause();
  if (cmd == "resume") return want(0, "resume"), cmdResume();
  if (cmd == "step") return want(1, "step N"), cmdStep(a);
  if (cmd == "stop") return want(0, "stop"), cmdStop();
  if (cmd == "wait") return want(0, "wait"), cmdWait();
  if (cmd == "status") return want(0, "status"), cmdStatus();
  if (cmd == "set") return cmdSet(rest);
  if (cmd == "get") return want(1, "get PATH"), cmdGet(a);
  if (cmd == "list") return want(1, "list actions"), cmdList(a);
  if (cmd == "do") return cmdDo(a);
  if (cmd == "plugins") return want(0, "plugins"), cmdPlugins();
  if (cmd == "reload") return want(1, "reload PLUGIN"), cmdReload(a);
  if (cmd == "swap") return want(2, "swap PATH TYPE"), cmdSwap(a);
  if (cmd == "save") return want(1, "save DIR"), cmdSave(a);
  if (cmd == "load-session") return cmdLoadSession(a);
  if (cmd == "help") return cmdHelp();
  if (cmd == "rate") return a.size() > 1 ? want(1, "rate [R]") : cmdRate(a);
  std::string near = closestMatch(cmd, commandNames());
  throw InputError("unknown command '" + cmd + "'" +
                   (near.empty() ? std::string("; type help") : "; did you mean '" + near + "'?"));
}

// ---- state helpers ------------------------------------------------------------------------------

std::shared_ptr<RunConfig> Shell::build(const ConfigDocument& doc) {
  auto run = buildRun(doc, plugins_);
  if (session_) {
    if (!run->pipeline) throw InputError("the config has no pipeline to restore the session into");
    run->pipeline->restoreSession(copyMaps(session_->maps.maps), session_->maps.edges,
                                  session_->localize);
  }
  return run;
}

void Shell::commit(ConfigDocument doc) {
  auto run = build(doc);
  joinWorker();
  exec_.reset();
  run_ = std::move(run);
  // Not assigned: assigning a yaml-cpp node would overwrite the old document's data in place.
  doc_.reset();
  doc_.emplace(std::move(doc));
  tree_used_ = false;
}

RunConfig& Shell::tree() {
  if (!run_) throw InputError("no config loaded (load CONFIG)");
  return *run_;
}

bool Shell::active() const {
  auto lk = lockBetweenFrames();
  return exec_ && state_ != State::kFinished && state_ != State::kIdle;
}

void Shell::requireIdle(const std::string& what) const {
  if (active()) throw InputError("cannot " + what + " while a run is in progress (stop it first)");
}

std::unique_lock<std::mutex> Shell::lockBetweenFrames() const {
  ++waiting_;
  std::unique_lock<std::mutex> lk(mutex_);
  --waiting_;
  return lk;
}

void Shell::joinWorker() {
  if (worker_.joinable()) worker_.join();
}

void Shell::reportWorkerError() {
  auto lk = lockBetweenFrames();
  if (!worker_error_.empty()) {
    ++errors_;
    *out_ << "error: the run failed: " << oneLine(worker_error_) << "\n";
    worker_error_.clear();
  }
}

void Shell::startExecution(int64_t budget) {
  if (!doc_) throw InputError("no config loaded (load CONFIG)");
  joinWorker();
  // A tree that processed frames has consumed its source: start from a fresh one.
  if (tree_used_ || !run_) {
    exec_.reset();
    run_ = build(*doc_);
  }
  tree_used_ = true;
  RunOptions o;
  o.out_dir = options_.out_dir;
  o.observer = options_.observer;
  o.rate = options_.rate;
  auto exec = std::make_unique<Execution>(*run_, o);
  {
    auto lk = lockBetweenFrames();
    exec_ = std::move(exec);
    state_ = State::kRunning;
    tellState("running");
    budget_ = budget;
    stop_requested_ = false;
    worker_error_.clear();
    report_.reset();
  }
  worker_ = std::thread(&Shell::workerLoop, this);
}

void Shell::workerLoop() {
  std::unique_lock<std::mutex> lk(mutex_);
  for (;;) {
    cv_.wait(lk, [&] { return stop_requested_ || state_ == State::kRunning; });
    if (stop_requested_) break;
    bool more = false;
    try {
      // Paced (rate > 0): wait for the frame's time with the lock released, so commands get in
      // meanwhile; a pause, a stop or a new rate ends the wait.
      const auto due = exec_->nextDue();
      if (PlaybackClock::Clock::now() < due) {
        cv_.wait_until(lk, due, [&] {
          return stop_requested_ || state_ != State::kRunning || exec_->nextDue() != due;
        });
        continue;
      }
      more = exec_->step();
    } catch (const std::exception& e) {
      worker_error_ = e.what();
    }
    if (!more) break;
    if (budget_ > 0 && --budget_ == 0) {
      state_ = State::kPaused;
      tellState("paused");
      cv_.notify_all();
    }
    // A command is waiting: let it in between two frames.
    if (waiting_ > 0) {
      lk.unlock();
      while (waiting_ > 0) std::this_thread::yield();
      lk.lock();
    }
  }
  try {
    report_ = exec_->finish(stop_requested_ ? "stopped" : worker_error_.empty() ? "" : "error");
  } catch (const std::exception& e) {
    if (worker_error_.empty()) worker_error_ = e.what();
  }
  state_ = State::kFinished;
  cv_.notify_all();
}

void Shell::printReport(const RunReport& r) {
  *out_ << fmt::format(
      "run finished ({}): {} frames in {:.3f} s ({:.1f} Hz), {} local maps, {}; outputs in {}\n",
      r.stopped_by, r.frames, r.wall_s, r.hz, r.local_maps, loopsClosedText(r.graph),
      options_.out_dir);
  if (r.ate_rmse)
    *out_ << scoreLine(r, run_ && run_->pipeline ? run_->pipeline->reference() : "");
}

// ---- commands -----------------------------------------------------------------------------------

void Shell::cmdLoad(const Args& a) {
  requireIdle("load a config");
  ConfigDocument doc = loadConfigFile(a[0]);
  auto saved = std::move(session_);
  session_.reset();
  try {
    commit(std::move(doc));
  } catch (...) {
    session_ = std::move(saved);
    throw;
  }
  *out_ << fmt::format("loaded {} ({} modules, {} plugins)\n", a[0], countModules(*run_) - 1,
                      plugins_.loaded().size());
}

void Shell::cmdValidate() {
  if (!doc_) throw InputError("no config loaded (load CONFIG)");
  auto run = buildRun(*doc_, plugins_);
  *out_ << doc_->file << ": OK (" << countModules(*run) - 1 << " modules, "
       << plugins_.loaded().size() << " plugins)\n";
}

void Shell::cmdRun() {
  {
    auto lk = lockBetweenFrames();
    if (exec_ && state_ == State::kRunning) throw InputError("already running");
    if (exec_ && state_ == State::kPaused)
      throw InputError("a run is paused: resume, step N or stop it");
  }
  startExecution(-1);
  *out_ << "running " << doc_->file << (session_ && session_->localize ? " (localization)" : "")
       << "\n";
}

void Shell::cmdPause() {
  auto lk = lockBetweenFrames();
  if (!exec_ || state_ != State::kRunning) throw InputError("no run in progress");
  state_ = State::kPaused;
  tellState("paused");
  *out_ << "paused at frame " << exec_->frames() << "\n";
}

void Shell::cmdResume() {
  {
    auto lk = lockBetweenFrames();
    if (!exec_ || state_ != State::kPaused) throw InputError("no paused run");
    state_ = State::kRunning;
    tellState("running");
    budget_ = -1;
  }
  cv_.notify_all();
  *out_ << "resumed\n";
}

void Shell::cmdStep(const Args& a) {
  const int64_t n = parseCount(a[0]);
  bool start = false;
  {
    auto lk = lockBetweenFrames();
    if (exec_ && state_ == State::kRunning) throw InputError("already running (pause it first)");
    if (exec_ && state_ == State::kPaused) {
      state_ = State::kRunning;
      tellState("running");
      budget_ = n;
    } else {
      start = true;
    }
  }
  if (start) startExecution(n);
  cv_.notify_all();
  auto lk = lockBetweenFrames();
  cv_.wait(lk, [&] { return state_ != State::kRunning; });
  if (state_ == State::kFinished) {
    lk.unlock();
    cmdWait();
    return;
  }
  *out_ << "paused at frame " << exec_->frames() << "\n";
}

void Shell::cmdRate(const Args& a) {
  if (a.empty()) {
    *out_ << fmt::format("rate {}{}\n", options_.rate,
                        options_.rate > 0 ? "" : " (as fast as possible)");
    return;
  }
  double rate = -1;
  try {
    size_t used = 0;
    rate = std::stod(a[0], &used);
    if (used != a[0].size()) rate = -1;
  } catch (const std::exception&) {
  }
  if (!(rate >= 0) || !std::isfinite(rate))
    throw InputError("rate: expected a number >= 0 (0: as fast as possible, 1: the data's own "
                     "speed), got '" + a[0] + "'");
  {
    auto lk = lockBetweenFrames();
    options_.rate = rate;
    if (exec_) exec_->setRate(rate);
  }
  cv_.notify_all();  // a worker waiting for a frame's time re-reads it
  *out_ << fmt::format("rate {}\n", rate);
}

void Shell::cmdStop() {
  {
    auto lk = lockBetweenFrames();
    if (!exec_ || state_ == State::kIdle) throw InputError("no run to stop");
    if (state_ != State::kFinished) stop_requested_ = true;
  }
  cv_.notify_all();
  joinWorker();
  reportWorkerError();
  auto lk = lockBetweenFrames();
  if (report_) printReport(*report_);
}

void Shell::cmdWait() {
  {
    auto lk = lockBetweenFrames();
    if (!exec_) throw InputError("no run to wait for");
    cv_.wait(lk, [&] { return state_ != State::kRunning; });
    if (state_ == State::kPaused) {
      *out_ << "paused at frame " << exec_->frames() << "\n";
      return;
    }
  }
  joinWorker();
  reportWorkerError();
  auto lk = lockBetweenFrames();
  if (report_) printReport(*report_);
}

void Shell::cmdStatus() {
  auto lk = lockBetweenFrames();
  if (!run_) {
    *out_ << "state: idle, no config loaded\n";
    return;
  }
  const State s = exec_ ? state_ : State::kIdle;
  std::string line = fmt::format("state: {}", stateName(static_cast<int>(s)));
  if (exec_) {
    const double t = exec_->elapsed();
    const uint64_t f = exec_->frames();
    line += fmt::format(", frame {}", f);
    if (exec_->total() > 0)
      line += fmt::format("/{} ({:.1f}%)", exec_->total(), 100.0 * f / exec_->total());
    double hz = report_ ? report_->hz : t > 0 ? f / t : 0.0;
    line += fmt::format(", {:.1f} Hz", hz);
  }
  Pipeline* p = run_->pipeline.get();
  if (p && p->tracker)
    line += fmt::format(", local maps {}, tracking failures {}", p->tracker->stats().local_maps,
                        p->tracker->stats().failed);
  if (p && p->graph) {
    GraphStats g = p->graph->stats();
    line += fmt::format(", graph {} nodes {} edges, loops closed {}", g.nodes, g.edges,
                        g.loops_accepted);
    if (g.loops_restored > 0) line += fmt::format(" (+{} restored)", g.loops_restored);
  }
  if (session_)
    line += fmt::format(", session {} ({})", session_->manifest.dir,
                        session_->localize ? "localization" : "mapping");
  *out_ << line << "\n";
}

void Shell::cmdSet(const std::string& rest) {
  requireIdle("change parameters");
  if (!doc_) throw InputError("no config loaded (load CONFIG)");
  std::string assignment = rest;
  const auto sp = rest.find_first_of(" \t");
  const auto eq = rest.find('=');
  if (eq == std::string::npos || (sp != std::string::npos && sp < eq)) {
    if (sp == std::string::npos) throw InputError("usage: set PATH VALUE");
    assignment = rest.substr(0, sp) + "=" + trim(rest.substr(sp));
  }
  // A deep copy: yaml-cpp nodes share their data, and assigning one overwrites what it refers to.
  ConfigDocument doc = *doc_;
  doc.root.reset(YAML::Clone(doc_->root));
  applyOverride(doc, assignment, "set " + rest);  // errors quote what was typed
  const std::string path = assignment.substr(0, assignment.find('='));
  commit(std::move(doc));
  // The value as the rebuilt module holds it; a list slot (e.g. "outputs") echoes the input.
  std::string shown = trim(assignment.substr(assignment.find('=') + 1));
  try {
    PathTarget t = resolvePath(*run_, path);
    shown = t.param ? t.param->valueText() : t.module->typeName();
  } catch (const InputError&) {
  }
  *out_ << path << " = " << shown << "\n";
}

void Shell::cmdGet(const Args& a) {
  auto lk = lockBetweenFrames();
  PathTarget t = resolvePath(tree(), a[0]);
  if (t.param) {
    *out_ << a[0] << " = " << t.param->valueText() << " (" << t.param->typeName()
         << (t.param->unit().empty() ? "" : ", " + t.param->unit()) << ")\n";
    return;
  }
  YAML::Emitter e;
  e << YAML::Flow << dumpConfig(*t.module);
  *out_ << a[0] << " = " << e.c_str() << "\n";
}

void Shell::cmdList(const Args& a) {
  if (a[0] != "actions") throw InputError("usage: list actions");
  auto lk = lockBetweenFrames();
  size_t n = 0;
  walkModules(tree(), [&](Configurable& c, const std::string& path) {
    for (const auto& action : c.actions()) {
      *out_ << "  " << path << "." << action.name << "  " << action.doc << "\n";
      ++n;
    }
  });
  if (n == 0) *out_ << "no module of this config has actions\n";
}

void Shell::cmdDo(const Args& a) {
  if (a.empty()) throw InputError("usage: do MODULE.ACTION [ARGS]");
  auto lk = lockBetweenFrames();
  std::string msg = invokeAction(tree(), a[0], Args(a.begin() + 1, a.end()));
  *out_ << (msg.empty() ? std::string("done") : msg) << "\n";
}

void Shell::cmdPlugins() {
  auto loaded = plugins_.loaded();
  if (loaded.empty()) *out_ << "no plugin loaded\n";
  for (const auto& p : loaded)
    *out_ << fmt::format("  {} {}  {} types{}  {}\n", p.name, p.version, p.types.size(),
                        plugins_.inUse(p.name) ? ", in use" : "", p.path);
}

void Shell::cmdReload(const Args& a) {
  requireIdle("reload a plugin");
  const std::string name = a[0];
  std::string path;
  for (const auto& p : plugins_.loaded())
    if (p.name == name) path = p.path;
  if (path.empty()) throw InputError("plugin '" + name + "' is not loaded (see: plugins)");
  // Every object of the plugin goes first, so its library is really unmapped and the new build
  // (same path) is mapped afresh; session scenes may hold its value types too.
  joinWorker();
  {
    auto lk = lockBetweenFrames();
    exec_.reset();
    state_ = State::kIdle;
  }
  run_.reset();
  if (session_) session_->maps = SessionMaps{};
  if (plugins_.inUse(name))
    throw Error("objects of plugin '" + name + "' are still alive; it cannot be unloaded");
  plugins_.unload(name);
  const PluginInfo& info = plugins_.load(path);
  *out_ << fmt::format("reloaded {} {} from {} ({} types)\n", info.name, info.version, info.path,
                      info.types.size());
  if (session_) session_->maps = loadSessionMaps(session_->manifest);
  if (doc_) {
    run_ = build(*doc_);
    tree_used_ = false;
    *out_ << "rebuilt " << countModules(*run_) - 1 << " modules from the current config\n";
  }
}

void Shell::cmdSwap(const Args& a) {
  requireIdle("swap a module");
  if (!doc_) throw InputError("no config loaded (load CONFIG)");
  const std::string& path = a[0];
  const std::string& type = a[1];
  PathTarget t = resolvePath(tree(), path);
  if (t.param || !t.slot) throw InputError("'" + path + "' is not a module");
  loadPluginOf(plugins_, type);
  auto info = Registry::instance().find(type);
  if (!info) {
    std::string near = Registry::instance().closest(type, t.slot->kind());
    throw InputError("unknown type '" + type + "'" +
                     (near.empty() ? std::string("") : "; did you mean '" + near + "'?"));
  }
  if (info->kind != t.slot->kind())
    throw InputError("'" + type + "' is " + withArticle(info->kind) + ", but '" + path +
                     "' takes " + withArticle(t.slot->kind()));
  // The new node keeps the keys the new type also has (and the instance name).
  std::vector<std::string> keys{"name"};
  {
    auto probe = Registry::instance().create(type);
    for (auto* p : probe->params()) keys.push_back(p->name());
    for (auto* s : probe->slots()) keys.push_back(s->name());
  }
  // A deep copy: yaml-cpp nodes share their data, and assigning one overwrites what it refers to.
  ConfigDocument doc = *doc_;
  doc.root.reset(YAML::Clone(doc_->root));
  YAML::Node cur = doc.root;
  const auto parts = splitPath(path);
  YAML::Node old;
  for (size_t i = 0; i < parts.size(); ++i) {
    const std::string& p = parts[i];
    YAML::Node next;
    if (p[0] == '[') {
      if (cur.IsSequence()) next.reset(cur[std::stoul(p.substr(1, p.size() - 2))]);
    } else if (cur.IsMap()) {
      next.reset(cur[p]);
    }
    if (i + 1 == parts.size()) {
      old.reset(next);
      break;
    }
    if (!next || !next.IsDefined() || next.IsNull() || next.IsScalar()) break;
    cur.reset(next);
  }
  YAML::Node node(YAML::NodeType::Map);
  node["type"] = type;
  std::vector<std::string> dropped;
  if (old && old.IsDefined() && old.IsMap()) {
    for (auto it = old.begin(); it != old.end(); ++it) {
      const std::string k = it->first.Scalar();
      if (k == "type") continue;
      if (std::find(keys.begin(), keys.end(), k) != keys.end())
        node[k] = it->second;
      else
        dropped.push_back(k);
    }
  }
  YAML::Emitter e;
  e << YAML::Flow << node;
  applyOverride(doc, path + "=" + e.c_str(), "swap " + path + " " + type);
  doc.overrides.erase(path);
  const std::string from = t.module->typeName();
  commit(std::move(doc));
  std::string d;
  for (const auto& k : dropped) d += (d.empty() ? "" : ", ") + k;
  *out_ << path << ": " << from << " -> " << type << (d.empty() ? "" : " (dropped: " + d + ")")
       << "\n";
}

void Shell::cmdSave(const Args& a) {
  auto lk = lockBetweenFrames();
  if (!doc_ || !run_) throw InputError("no config loaded (load CONFIG)");
  if (!run_->pipeline) throw InputError("the config has no pipeline");
  SessionSummary s = saveSession(a[0], resolvedYaml(*doc_), *run_->pipeline);
  *out_ << fmt::format("saved session {}: {} local maps, {} edges, {} poses{}\n", a[0], s.maps,
                      s.edges, s.poses, s.graph_file ? ", graph.g2o" : "");
}

void Shell::cmdLoadSession(const Args& a) {
  if (a.empty() || a.size() > 2 || (a.size() == 2 && a[1] != "--localize"))
    throw InputError("usage: load-session DIR [--localize]");
  requireIdle("load a session");
  LoadedSession ls;
  ls.manifest = readSessionManifest(a[0]);
  ls.localize = a.size() == 2;
  ConfigDocument doc = loadConfigText(ls.manifest.config_text, ls.manifest.config_path);
  // The config's plugins first: the scenes hold their value types.
  buildRun(doc, plugins_);
  ls.maps = loadSessionMaps(ls.manifest);
  auto saved = std::move(session_);
  session_ = std::move(ls);
  try {
    commit(std::move(doc));
  } catch (...) {
    session_ = std::move(saved);
    throw;
  }
  *out_ << fmt::format(
      "loaded session {}: {} local maps, {} edges ({})\n", a[0], session_->maps.maps.size(),
      session_->maps.edges.size(),
      session_->localize ? "localization: the maps are frozen" : "mapping: new maps are appended");
}

void Shell::cmdHelp() {
  for (const auto& c : kCommands) *out_ << fmt::format("  {:<32} {}\n", c.usage, c.doc);
}

// ---- the loop -----------------------------------------------------------------------------------

namespace {

char* completeCommand(const char* text, int state) {
  static size_t index;
  if (state == 0) index = 0;
  const auto& names = Shell::commandNames();
  const size_t len = std::strlen(text);
  while (index < names.size()) {
    const std::string& n = names[index++];
    if (n.compare(0, len, text) == 0) return strdup(n.c_str());
  }
  return nullptr;
}

char** completion(const char* text, int start, int) {
  rl_attempted_completion_over = 0;
  // Commands complete at the start of the line; file names elsewhere (readline's default).
  return start == 0 ? rl_completion_matches(text, completeCommand) : nullptr;
}

}  // namespace

int runShellLoop(Shell& shell, std::istream& in, bool interactive) {
  if (interactive) {
    std::string history;
    if (const char* home = std::getenv("HOME")) history = std::string(home) + "/.plugslam_history";
    using_history();
    if (!history.empty()) read_history(history.c_str());
    rl_attempted_completion_function = completion;
    std::cout << "plugslam shell; type help\n";
    while (char* raw = readline("plugslam> ")) {
      std::string line(raw);
      std::free(raw);
      if (!trim(line).empty()) add_history(line.c_str());
      if (!shell.execute(line)) break;
    }
    if (!history.empty()) {
      write_history(history.c_str());
      history_truncate_file(history.c_str(), 1000);
    }
    return 0;
  }
  std::string line;
  while (std::getline(in, line))
    if (!shell.execute(line)) break;
  return shell.errors() > 0 ? 1 : 0;
}

}  // namespace plugslam::runtime
