// plugslam view HOST:PORT: the address of the built-in page of a host streaming with --serve
// (`plugslam run --serve` on a robot, the page opened on a laptop), printed or opened.
#include <CLI/CLI.hpp>
#include <cstdlib>
#include <iostream>

#include "cli.h"
#include "commands/commands.h"
#include "plugslam/errors.h"

namespace plugslam::runtime {

namespace {

// "HOST:PORT", "HOST" (port 8765), ":PORT" or "PORT" (host 127.0.0.1); [v6]:PORT too.
std::string pageUrl(const std::string& text) {
  std::string host = "127.0.0.1", port = "8765";
  const size_t colon = text.rfind(':');
  const bool v6 = !text.empty() && text.front() == '[';
  if (v6) {
    const size_t close = text.find(']');
    if (close == std::string::npos) throw InputError("'" + text + "': expected [IPv6]:PORT");
    host = text.substr(0, close + 1);
    if (close + 1 < text.size()) {
      if (text[close + 1] != ':') throw InputError("'" + text + "': expected [IPv6]:PORT");
      port = text.substr(close + 2);
    }
  } else if (colon != std::string::npos) {
    if (colon > 0) host = text.substr(0, colon);
    port = text.substr(colon + 1);
  } else if (!text.empty() && text.find_first_not_of("0123456789") == std::string::npos) {
    port = text;
  } else if (!text.empty()) {
    host = text;
  }
  int p = 0;
  try {
    size_t used = 0;
    p = std::stoi(port, &used);
    if (used != port.size()) p = 0;
  } catch (const std::exception&) {
    p = 0;
  }
  if (p < 1 || p > 65535) throw InputError("'" + text + "': the port must be 1 to 65535");
  if (host.find_first_of(" /?#@") != std::string::npos)
    throw InputError("'" + text + "': '" + host + "' is not a host name or address");
  return "http://" + host + ":" + std::to_string(p) + "/";
}

}  // namespace

void addViewCommand(CLI::App& root, int& exit_code) {
  auto* cmd = root.add_subcommand(
      "view", "Print (or --open) the page of a host that streams with --serve");
  static std::string address;
  static bool open = false;
  cmd->add_option("HOST:PORT", address, "the host's --serve address (default 127.0.0.1:8765)");
  cmd->add_flag("--open", open, "open the page in the desktop's browser (xdg-open)");
  cmd->callback([&exit_code] {
    const std::string url = pageUrl(address);
    std::cout << url << "\n";
    exit_code = kOk;
    if (!open) return;
    if (std::system("command -v xdg-open > /dev/null 2>&1") != 0)
      throw InputError("no xdg-open here to open a browser: open " + url + " yourself");
    // The URL is ours (checked above): no shell metacharacters reach the command.
    if (std::system(("xdg-open '" + url + "' > /dev/null 2>&1 &").c_str()) != 0)
      throw Error("xdg-open failed for " + url);
  });
}

}  // namespace plugslam::runtime
