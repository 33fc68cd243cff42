#include "plugin_manager.h"

#include <spdlog/spdlog.h>

#include <boost/dll/runtime_symbol_info.hpp>
#include <boost/dll/shared_library.hpp>
#include <boost/filesystem.hpp>
#include <cstdlib>
#include <sstream>

#include "build_paths.h"
#include "plugslam/errors.h"
#include "plugslam/plugin.h"
#include "plugslam/value_types.h"
#include "plugslam/view/drawers.h"

namespace plugslam::runtime {

namespace fs = boost::filesystem;

struct PluginManager::Loaded {
  PluginInfo info;
  std::shared_ptr<boost::dll::shared_library> library;
};

namespace {

std::map<std::string, std::string> parseFingerprint(const std::string& s) {
  std::map<std::string, std::string> out;
  std::istringstream in(s);
  std::string item;
  while (std::getline(in, item, ';')) {
    auto eq = item.find('=');
    if (eq != std::string::npos) out[item.substr(0, eq)] = item.substr(eq + 1);
  }
  return out;
}

bool looksLikePath(const std::string& s) {
  return s.find('/') != std::string::npos ||
         (s.size() > 3 && s.compare(s.size() - 3, 3, ".so") == 0);
}

std::string joinList(const std::vector<std::string>& v) {
  std::string out;
  for (const auto& s : v) out += (out.empty() ? "" : ", ") + s;
  return out;
}

}  // namespace

std::string pluginFileName(const std::string& name) { return "plugslam_" + name + ".so"; }

PluginManager::PluginManager(Registry& registry) : registry_(registry) {}

PluginManager::~PluginManager() {
  // Types go, libraries stay mapped while objects made by them live (their deleters hold them).
  for (auto& [name, p] : plugins_) {
    registry_.removePlugin(name);
    ValueTypes::instance().removeOwner(name);
    view::Drawers::instance().removeOwner(name);
  }
}

void PluginManager::addSearchDir(const std::string& dir) {
  for (const auto& d : extra_dirs_)
    if (d == dir) return;
  extra_dirs_.push_back(dir);
}

std::vector<std::string> PluginManager::searchPath() const {
  std::vector<std::string> dirs = extra_dirs_;
  if (const char* env = std::getenv("PLUGSLAM_PLUGIN_PATH")) {
    std::istringstream in(env);
    std::string d;
    while (std::getline(in, d, ':'))
      if (!d.empty()) dirs.push_back(d);
  }
  fs::path exe = boost::dll::program_location();
  // Installed layout: <prefix>/bin/plugslam and <prefix>/lib/plugslam/plugins.
  dirs.push_back((exe.parent_path().parent_path() / "lib" / "plugslam" / "plugins").string());
  dirs.push_back(build_paths::defaultPluginDir());
  // Running from the build tree (tests, developers): the build's plugin folder.
  fs::path build_plugins(build_paths::buildPluginDir());
  boost::system::error_code ec;
  fs::path build_root = fs::canonical(build_plugins.parent_path(), ec);
  if (!ec) {
    fs::path canon_exe = fs::canonical(exe, ec);
    if (!ec && canon_exe.string().rfind(build_root.string() + "/", 0) == 0)
      dirs.push_back(build_plugins.string());
  }
  std::vector<std::string> unique;
  for (auto& d : dirs) {
    bool seen = false;
    for (auto& u : unique) seen = seen || u == d;
    if (!seen) unique.push_back(d);
  }
  return unique;
}

std::string PluginManager::resolve(const std::string& name_or_path) const {
  // Non-throwing checks: a name from a config (too long, odd characters) is simply not found.
  boost::system::error_code ec;
  if (looksLikePath(name_or_path)) return fs::exists(name_or_path, ec) ? name_or_path : "";
  for (const auto& dir : searchPath()) {
    fs::path p = fs::path(dir) / pluginFileName(name_or_path);
    if (fs::exists(p, ec)) return p.string();
  }
  return "";
}

std::vector<std::string> PluginManager::discover() const {
  std::vector<std::string> found;
  std::vector<std::string> names;
  for (const auto& dir : searchPath()) {
    boost::system::error_code ec;
    if (!fs::is_directory(dir, ec)) continue;
    std::vector<fs::path> files;
    for (fs::directory_iterator it(dir, ec), end; !ec && it != end; it.increment(ec)) {
      std::string f = it->path().filename().string();
      if (f.rfind("plugslam_", 0) == 0 && f.size() > 12 && f.compare(f.size() - 3, 3, ".so") == 0)
        files.push_back(it->path());
    }
    std::sort(files.begin(), files.end());
    for (const auto& f : files) {
      std::string n = f.filename().string();
      n = n.substr(9, n.size() - 12);
      if (std::find(names.begin(), names.end(), n) != names.end()) continue;
      names.push_back(n);
      found.push_back(f.string());
    }
  }
  return found;
}

const PluginInfo& PluginManager::load(const std::string& name_or_path) {
  std::string path = resolve(name_or_path);
  if (path.empty()) {
    if (looksLikePath(name_or_path))
      throw PluginError("plugin file '" + name_or_path + "' does not exist");
    throw PluginError("plugin '" + name_or_path + "' not found (looked for " +
                      pluginFileName(name_or_path) + " in: " + joinList(searchPath()) + ")");
  }
  boost::system::error_code ec;
  std::string canon = fs::canonical(path, ec).string();
  if (ec) canon = path;
  for (auto& [name, p] : plugins_)
    if (p->info.path == canon) return p->info;

  auto lib = std::make_shared<boost::dll::shared_library>();
  // RTLD_NOW: an unresolved symbol is refused here, not as a crash at its first call.
  lib->load(canon, boost::dll::load_mode::rtld_now | boost::dll::load_mode::rtld_local, ec);
  if (ec || !lib->is_loaded()) {
    const char* why = dlerror();
    throw PluginError("cannot load plugin '" + name_or_path + "' (" + canon +
                      "): " + (why ? std::string(why) : ec.message()));
  }
  if (!lib->has(kPlugslamDescriptorSymbol))
    throw PluginError("'" + canon + "' is not a plugslam plugin: it exports no " +
                      kPlugslamDescriptorSymbol + "() entry");
  auto entry = lib->get<const PlugslamPluginDescriptor*()>(kPlugslamDescriptorSymbol);
  const PlugslamPluginDescriptor* d = entry();
  if (d == nullptr || d->magic != kPlugslamPluginMagic)
    throw PluginError("'" + canon +
                      "' is not a plugslam plugin: its descriptor has a wrong magic number");
  std::string name = d->name ? d->name : "";
  std::string sdk = d->sdk_version ? d->sdk_version : "?";
  std::string who = "plugin '" + name + "' (" + canon + ")";
  std::string host_abi =
      std::to_string(PLUGSLAM_ABI_MAJOR) + "." + std::to_string(PLUGSLAM_ABI_MINOR);
  std::string plugin_abi = std::to_string(d->abi_major) + "." + std::to_string(d->abi_minor);
  if (d->abi_major != PLUGSLAM_ABI_MAJOR)
    throw PluginError(who + " was built for plugin ABI " + plugin_abi + " (SDK " + sdk +
                      "), but this host speaks ABI " + host_abi + " (SDK " +
                      PLUGSLAM_VERSION_STRING + "); rebuild it against this SDK");
  if (d->abi_minor > PLUGSLAM_ABI_MINOR)
    throw PluginError(who + " needs plugin ABI " + plugin_abi + " (SDK " + sdk +
                      "), newer than this host's ABI " + host_abi + " (SDK " +
                      PLUGSLAM_VERSION_STRING + "); update plugslam");
  auto theirs = parseFingerprint(d->build_fingerprint ? d->build_fingerprint : "");
  auto ours = parseFingerprint(hostBuildFingerprint());
  std::vector<std::string> diffs;
  for (const auto& [key, value] : ours) {
    auto it = theirs.find(key);
    std::string v = it == theirs.end() ? "(missing)" : it->second;
    if (v != value) diffs.push_back(key + "=" + v + " where the host has " + key + "=" + value);
  }
  if (!diffs.empty())
    throw PluginError(who + " was built with " + joinList(diffs) +
                      "; rebuild it with the host's toolchain and settings");
  if (name.empty() || name.find('.') != std::string::npos)
    throw PluginError("'" + canon + "' declares an invalid plugin name '" + name + "'");
  if (auto it = plugins_.find(name); it != plugins_.end())
    throw PluginError(who + " has the same name as the plugin already loaded from " +
                      it->second->info.path);
  if (!looksLikePath(name_or_path) && name != name_or_path)
    spdlog::warn("plugin file {} declares the name '{}', not '{}'", canon, name, name_or_path);

  Registrar registrar(registry_, name, std::static_pointer_cast<void>(lib));
  char err[1024] = {0};
  int rc = d->register_types ? d->register_types(&registrar, err, sizeof(err)) : 1;
  if (rc != 0) {
    registry_.removePlugin(name);
    ValueTypes::instance().removeOwner(name);
    view::Drawers::instance().removeOwner(name);
    throw PluginError(who + " failed to register its types: " +
                      (err[0] ? std::string(err) : std::string("no register function")));
  }
  auto loaded = std::make_unique<Loaded>();
  loaded->info = PluginInfo{name,
                            d->version ? d->version : "",
                            d->description ? d->description : "",
                            sdk,
                            canon,
                            registrar.added()};
  loaded->library = lib;
  spdlog::debug("loaded plugin {} {} from {} ({} types)", name, loaded->info.version, canon,
                loaded->info.types.size());
  auto& ref = *loaded;
  plugins_[name] = std::move(loaded);
  return ref.info;
}

bool PluginManager::isLoaded(const std::string& name) const { return plugins_.count(name) > 0; }

std::vector<PluginInfo> PluginManager::loaded() const {
  std::vector<PluginInfo> out;
  for (auto& [name, p] : plugins_) out.push_back(p->info);
  return out;
}

void PluginManager::unload(const std::string& name) {
  auto it = plugins_.find(name);
  if (it == plugins_.end()) throw InputError("plugin '" + name + "' is not loaded");
  registry_.removePlugin(name);
  ValueTypes::instance().removeOwner(name);
  view::Drawers::instance().removeOwner(name);
  plugins_.erase(it);
}

bool PluginManager::inUse(const std::string& name) const {
  auto it = plugins_.find(name);
  return it != plugins_.end() && it->second->library.use_count() > 1;
}

}  // namespace plugslam::runtime
