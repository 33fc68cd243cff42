// The viewer server's HTTP side and its refusals, over plain sockets: the page's files are served
// from their folder and nothing outside it, a WebSocket upgrade needs a Foxglove subprotocol, a
// non-loopback address needs --serve-remote, a taken port is a clear error.
#include <arpa/inet.h>
#include <gtest/gtest.h>
#include <netinet/in.h>
#include <sys/socket.h>
#include <unistd.h>

#include <boost/filesystem.hpp>
#include <fstream>

#include "plugslam/errors.h"
#include "temp_dir.h"
#include "view/foxglove_server.h"

namespace plugslam::runtime {
namespace {

namespace fs = boost::filesystem;

// Sends `request` to 127.0.0.1:port and returns the whole response (the server closes or the
// read times out after 2 s).
std::string roundTrip(uint16_t port, const std::string& request) {
  const int s = ::socket(AF_INET, SOCK_STREAM, 0);
  sockaddr_in a{};
  a.sin_family = AF_INET;
  a.sin_port = htons(port);
  a.sin_addr.s_addr = htonl(INADDR_LOOPBACK);
  if (::connect(s, reinterpret_cast<sockaddr*>(&a), sizeof(a)) != 0) {
    ::close(s);
    return "";
  }
  timeval tv{2, 0};
  ::setsockopt(s, SOL_SOCKET, SO_RCVTIMEO, &tv, sizeof(tv));
  (void)!::write(s, request.data(), request.size());
  std::string out;
  char buf[4096];
  for (ssize_t n; (n = ::read(s, buf, sizeof(buf))) > 0;) {
    out.append(buf, static_cast<size_t>(n));
    if (out.find("\r\n\r\n") != std::string::npos && request.find("Connection: close") == std::string::npos &&
        out.find("Content-Length") != std::string::npos) {
      const auto head = out.find("\r\n\r\n");
      const auto cl = out.find("Content-Length: ");
      const size_t length = std::stoul(out.substr(cl + 16));
      if (out.size() >= head + 4 + length) break;
    }
  }
  ::close(s);
  return out;
}

std::string get(uint16_t port, const std::string& target) {
  return roundTrip(port, "GET " + target + " HTTP/1.1\r\nHost: x\r\n\r\n");
}

class ServerTest : public ::testing::Test {
 protected:
  void SetUp() override {
    root_ = tmp_.path().string();
    tmp_.write("web/index.html", "<html>page</html>");  // checked writes
    tmp_.write("web/js/app.js", "console.log(1)");
    tmp_.write("secret.txt", "secret");
    fs::create_symlink(root_ / "secret.txt", root_ / "web" / "link.txt");
  }
  plugslam::testing::TempDir tmp_{"plugslam_web"};  // fresh, of this test's own, removed after
  fs::path root_;
  ViewHub hub_;
};

TEST_F(ServerTest, ServesThePagesFilesAndNothingOutside) {
  ViewServerOptions o;
  o.port = 0;
  o.web_root = (root_ / "web").string();
  FoxgloveServer server(hub_, nullptr, o);
  server.start();
  const uint16_t port = server.port();
  const std::string index = get(port, "/");
  EXPECT_NE(index.find("200 OK"), std::string::npos);
  EXPECT_NE(index.find("text/html"), std::string::npos);
  EXPECT_NE(index.find("<html>page</html>"), std::string::npos);
  const std::string js = get(port, "/js/app.js?v=1");
  EXPECT_NE(js.find("text/javascript"), std::string::npos);
  EXPECT_NE(js.find("console.log(1)"), std::string::npos);
  for (const char* outside : {"/../secret.txt", "/js/../../secret.txt", "/%2e%2e/secret.txt"})
    EXPECT_NE(get(port, outside).find("400 Bad Request"), std::string::npos) << outside;
  EXPECT_NE(get(port, "/link.txt").find("404 Not Found"), std::string::npos);  // a symlink out
  EXPECT_EQ(get(port, "/link.txt").find("secret"), std::string::npos);
  EXPECT_NE(get(port, "/missing.js").find("404"), std::string::npos);
  EXPECT_NE(roundTrip(port, "POST / HTTP/1.1\r\nHost: x\r\nContent-Length: 0\r\n\r\n").find("405"),
            std::string::npos);
  // The WebSocket handshake without a Foxglove subprotocol.
  const std::string upgrade = roundTrip(
      port, "GET / HTTP/1.1\r\nHost: x\r\nUpgrade: websocket\r\nConnection: Upgrade\r\n"
            "Sec-WebSocket-Key: dGhlIHNhbXBsZSBub25jZQ==\r\nSec-WebSocket-Version: 13\r\n"
            "Sec-WebSocket-Protocol: chat\r\n\r\n");
  EXPECT_NE(upgrade.find("400"), std::string::npos);
  EXPECT_NE(upgrade.find("foxglove.websocket.v1"), std::string::npos);
  // With one: switched, and the offered protocol echoed.
  const std::string ws = roundTrip(
      port, "GET / HTTP/1.1\r\nHost: x\r\nUpgrade: websocket\r\nConnection: Upgrade\r\n"
            "Sec-WebSocket-Key: dGhlIHNhbXBsZSBub25jZQ==\r\nSec-WebSocket-Version: 13\r\n"
            "Sec-WebSocket-Protocol: x, foxglove.websocket.v1\r\n\r\n");
  EXPECT_NE(ws.find("101 Switching Protocols"), std::string::npos);
  EXPECT_NE(ws.find("Sec-WebSocket-Protocol: foxglove.websocket.v1"), std::string::npos);
  // Garbage instead of HTTP: the connection goes, the server stays.
  roundTrip(port, std::string("\x16\x03\x01\x00\xff garbage\r\n\r\n", 20));
  EXPECT_NE(get(port, "/").find("200 OK"), std::string::npos);
}

TEST_F(ServerTest, WithoutThePageAnIndexSaysHowToConnect) {
  ViewServerOptions o;
  o.port = 0;
  FoxgloveServer server(hub_, nullptr, o);
  server.start();
  const std::string index = get(server.port(), "/");
  EXPECT_NE(index.find("200 OK"), std::string::npos);
  EXPECT_NE(index.find(server.url()), std::string::npos);
}

TEST_F(ServerTest, RefusesRemoteAddressesUnlessAskedAndTakenPorts) {
  ViewServerOptions o;
  o.address = "0.0.0.0";
  o.port = 0;
  try {
    FoxgloveServer(hub_, nullptr, o).start();
    ADD_FAILURE() << "a non-loopback address was accepted";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("--serve-remote"), std::string::npos);
  }
  o.address = "not-an-ip";
  EXPECT_THROW(FoxgloveServer(hub_, nullptr, o).start(), InputError);
  ViewServerOptions first;
  first.port = 0;
  FoxgloveServer a(hub_, nullptr, first);
  a.start();
  ViewServerOptions second;
  second.port = a.port();
  try {
    FoxgloveServer(hub_, nullptr, second).start();
    ADD_FAILURE() << "a taken port was accepted";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("cannot listen"), std::string::npos);
  }
}

}  // namespace
}  // namespace plugslam::runtime
