// The viewer's HTTP server over real sockets: what it serves, what it refuses (path traversal, bad
// requests, other methods, heads beyond the limit), that slow, idle, unfinished and huge requests
// hold back no other client, and the live stream with a stalled client and 20 clients at once.
#include "starnav/config.hpp"
#if STARNAV_HAVE_HTTP
#include <arpa/inet.h>
#include <gtest/gtest.h>
#include <netinet/in.h>
#include <sys/socket.h>
#include <unistd.h>

#include <poll.h>

#include <algorithm>
#include <atomic>
#include <chrono>
#include <filesystem>
#include <fstream>
#include <string>
#include <thread>
#include <vector>

#include "starnav/core/error.hpp"
#include "starnav/view/run_server.hpp"
#include "support/raw_http.hpp"

namespace starnav {
namespace {

namespace fs = std::filesystem;

struct TempTree {
  fs::path root;
  TempTree() {
    root = fs::temp_directory_path() / ("starnav_view_test_" + std::to_string(::getpid()) + "_" + std::to_string(counter()++));
    fs::remove_all(root);
    fs::create_directories(root / "run");
    fs::create_directories(root / "viewer");
    write("viewer/index.html", "<html>viewer</html>");
    write("viewer/viewer.js", "console.log('viewer');");
    write("run/world.json", "{\"schema\":\"starnav-world\",\"version\":1}");
    write("run/steps.jsonl", std::string(300000, 'x') + "\n");
    write("secret.txt", "outside the run folder");
    write("run/.hidden", "hidden");
    fs::create_symlink(root / "secret.txt", root / "run" / "link.txt");
  }
  ~TempTree() {
    std::error_code ec;
    fs::remove_all(root, ec);
  }
  void write(const std::string& rel, const std::string& text) const { std::ofstream(root / rel, std::ios::binary) << text; }
  static int& counter() {
    static int n = 0;
    return n;
  }
};

using test::http_get;
using test::raw_http_request;

int status_of(const std::string& response) {
  if (response.rfind("HTTP/1.1 ", 0) != 0) return -1;
  return std::stoi(response.substr(9, 3));
}

std::size_t count_of(const std::string& text, const std::string& what) {
  std::size_t n = 0;
  for (std::size_t at = text.find(what); at != std::string::npos; at = text.find(what, at + what.size())) ++n;
  return n;
}

RunServerOptions options_for(const TempTree& t, bool live = false) {
  RunServerOptions o;
  o.run_dir = (t.root / "run").string();
  o.viewer_dir = (t.root / "viewer").string();
  o.live = live;
  return o;
}

TEST(RunServer, ServesTheViewerAndTheRunsFiles) {
  TempTree t;
  RunServer server(options_for(t));
  server.start();
  ASSERT_GT(server.port(), 0);
  EXPECT_EQ(server.url(), "http://127.0.0.1:" + std::to_string(server.port()) + "/");
  const std::string index = http_get(server.port(), "/");
  EXPECT_EQ(status_of(index), 200);
  EXPECT_NE(index.find("<html>viewer</html>"), std::string::npos);
  EXPECT_NE(index.find("text/html"), std::string::npos);
  const std::string js = http_get(server.port(), "/viewer.js");
  EXPECT_EQ(status_of(js), 200);
  EXPECT_NE(js.find("text/javascript"), std::string::npos);
  const std::string world = http_get(server.port(), "/run/world.json");
  EXPECT_EQ(status_of(world), 200);
  EXPECT_NE(world.find("{\"schema\":\"starnav-world\",\"version\":1}"), std::string::npos);
  // A file larger than a read chunk arrives whole.
  const std::string steps = http_get(server.port(), "/run/steps.jsonl");
  EXPECT_EQ(status_of(steps), 200);
  const std::size_t body = steps.find("\r\n\r\n") + 4;
  EXPECT_EQ(steps.substr(body), std::string(300000, 'x') + "\n");
  // HEAD answers without a body.
  const std::string head = raw_http_request(server.port(), "HEAD /run/world.json HTTP/1.1\r\nHost: x\r\nConnection: close\r\n\r\n");
  EXPECT_EQ(status_of(head), 200);
  EXPECT_EQ(head.find("starnav-world"), std::string::npos);
  // Memory files are served before (and instead of) the folder's.
  server.set_memory_file("world.json", "{\"live\":true}");
  EXPECT_NE(http_get(server.port(), "/run/world.json").find("{\"live\":true}"), std::string::npos);
}

TEST(RunServer, RefusesPathTraversalAndHiddenOrLinkedFiles) {
  TempTree t;
  RunServer server(options_for(t));
  server.start();
  for (const std::string target :
       {"/run/../secret.txt", "/run/..%2Fsecret.txt", "/run/%2e%2e%2fsecret.txt", "/run/%2E%2E/secret.txt", "/../secret.txt",
        "/run/..", "/run/.hidden", "/run/link.txt", "/run/run/world.json", "/run/", "/secret.txt", "/run/world.json%00.png",
        "/run//etc/passwd", "/run/%2Fetc%2Fpasswd", "/viewer/index.html", "/index.html/.."}) {
    const std::string r = http_get(server.port(), target);
    EXPECT_EQ(r.find("outside the run folder"), std::string::npos) << target;
    EXPECT_EQ(r.find("hidden"), std::string::npos) << target;
    EXPECT_GE(status_of(r), 400) << target;
    EXPECT_LT(status_of(r), 500) << target;
  }
}

TEST(RunServer, AnswersBadRequestsWith4xx) {
  TempTree t;
  RunServer server(options_for(t));
  server.start();
  const int port = server.port();
  EXPECT_EQ(status_of(raw_http_request(port, "POST /run/world.json HTTP/1.1\r\nHost: x\r\nContent-Length: 2\r\nConnection: close\r\n\r\nab")), 405);
  EXPECT_EQ(status_of(raw_http_request(port, "DELETE /run/world.json HTTP/1.1\r\nHost: x\r\nConnection: close\r\n\r\n")), 405);
  EXPECT_EQ(status_of(http_get(port, "/nothing-here")), 404);
  EXPECT_EQ(status_of(http_get(port, "/events")), 404);  // not a live server
  // (cpp-httplib answers these at once, then waits out its read timeout before closing: 1 s is enough.)
  const int garbage = status_of(raw_http_request(port, "THIS IS NOT HTTP\r\n\r\n", 1000));
  EXPECT_GE(garbage, 400);
  EXPECT_LT(garbage, 500);
  // A body over the 64 KiB limit: 413 once it has been read.
  const std::string big_body = "POST / HTTP/1.1\r\nHost: x\r\nContent-Length: 200000\r\nConnection: close\r\n\r\n" + std::string(200000, 'b');
  const int body = status_of(raw_http_request(port, big_body));
  EXPECT_EQ(body, 413);
  // Still serving after all that.
  EXPECT_EQ(status_of(http_get(port, "/run/world.json")), 200);
}

// A client that never reads: the publisher never waits for it, the other clients get everything,
// and the server drops it after the write timeout.
TEST(RunServer, AStalledLiveClientHoldsBackNeitherThePublisherNorTheOthers) {
  TempTree t;
  RunServerOptions o = options_for(t, true);
  o.write_timeout_s = 0.5;
  RunServer server(o);
  server.start();
  const int port = server.port();
  // The stalled client: a small receive buffer, connected and never read from.
  const int stalled = test::connect_loopback(port, 4096);
  ASSERT_GE(stalled, 0);
  const std::string request = "GET /events HTTP/1.1\r\nHost: x\r\n\r\n";
  ASSERT_EQ(::send(stalled, request.data(), request.size(), MSG_NOSIGNAL), static_cast<ssize_t>(request.size()));
  while (server.live_clients() < 1) std::this_thread::sleep_for(std::chrono::milliseconds(5));

  std::string reader_got;
  std::thread reader([&] { reader_got = http_get(port, "/events"); });
  while (server.live_clients() < 2) std::this_thread::sleep_for(std::chrono::milliseconds(5));
  // 20 MB of steps: far more than any socket buffer holds.
  const std::string line = "{\"t_s\":1.0,\"hits\":\"" + std::string(10000, 'h') + "\"}";
  for (int i = 0; i < 2000; ++i) server.publish("step", line);
  server.end_live();
  reader.join();
  EXPECT_EQ(count_of(reader_got, "event: step"), 2000u);
  EXPECT_EQ(count_of(reader_got, "event: end"), 1u);
  EXPECT_EQ(server.events_published(), 2001u);
  // The stalled client is dropped by the write timeout.
  const auto deadline = std::chrono::steady_clock::now() + std::chrono::seconds(30);
  while (server.live_clients() > 0 && std::chrono::steady_clock::now() < deadline)
    std::this_thread::sleep_for(std::chrono::milliseconds(20));
  EXPECT_EQ(server.live_clients(), 0u);
  ::close(stalled);
}

TEST(RunServer, TwentyLiveClientsEachGetEveryStep) {
  TempTree t;
  RunServer server(options_for(t, true));
  server.start();
  const int port = server.port();
  constexpr int kClients = 20;
  std::vector<std::string> got(kClients);
  std::vector<std::thread> clients;
  for (int i = 0; i < kClients; ++i) clients.emplace_back([&, i] { got[static_cast<std::size_t>(i)] = http_get(port, "/events"); });
  while (server.live_clients() < static_cast<std::size_t>(kClients)) std::this_thread::sleep_for(std::chrono::milliseconds(5));
  // Files are still served while every live stream holds a thread.
  EXPECT_EQ(status_of(http_get(port, "/run/world.json")), 200);
  for (int i = 0; i < 500; ++i) server.publish("step", "{\"i\":" + std::to_string(i) + "}");
  server.end_live();
  EXPECT_TRUE(server.wait_drained(30.0));
  for (std::thread& c : clients) c.join();
  for (const std::string& g : got) {
    EXPECT_EQ(count_of(g, "event: step"), 500u);
    EXPECT_NE(g.find("data: {\"i\":499}"), std::string::npos);
    EXPECT_EQ(count_of(g, "event: end"), 1u);
  }
}

TEST(RunServer, RefusesLiveClientsBeyondItsLimitWith503) {
  TempTree t;
  RunServerOptions o = options_for(t, true);
  o.max_live_clients = 2;
  RunServer server(o);
  server.start();
  const int port = server.port();
  std::vector<std::thread> clients;
  for (int i = 0; i < 2; ++i) clients.emplace_back([port] { http_get(port, "/events"); });
  while (server.live_clients() < 2) std::this_thread::sleep_for(std::chrono::milliseconds(5));
  EXPECT_EQ(status_of(http_get(port, "/events")), 503);
  server.end_live();
  for (std::thread& c : clients) c.join();
}

void send_all(int fd, const std::string& bytes) { (void)::send(fd, bytes.data(), bytes.size(), MSG_NOSIGNAL); }

// `count` clients that have sent the start of a request's head and not its end.
std::vector<int> unfinished_requests(int port, int count) {
  std::vector<int> fds;
  for (int i = 0; i < count; ++i) {
    fds.push_back(test::connect_loopback(port));
    if (fds.back() >= 0) send_all(fds.back(), "GET /run/world.json HTTP/1.1\r\nHost: x\r\n");
  }
  return fds;
}

// Everything the server sends until it closes, or until nothing arrives for timeout_ms.
std::string read_until_closed(int fd, int timeout_ms) {
  std::string out;
  char buffer[65536];
  for (;;) {
    pollfd p{fd, POLLIN, 0};
    if (::poll(&p, 1, timeout_ms) <= 0) break;
    const ssize_t n = ::recv(fd, buffer, sizeof buffer, 0);
    if (n <= 0) break;
    out.append(buffer, static_cast<std::size_t>(n));
  }
  return out;
}

// True when the server has closed the connection (a read sees the end, or a reset) within timeout_ms.
bool closed_by_server(int fd, int timeout_ms) {
  const auto deadline = std::chrono::steady_clock::now() + std::chrono::milliseconds(timeout_ms);
  char buffer[4096];
  while (std::chrono::steady_clock::now() < deadline) {
    pollfd p{fd, POLLIN, 0};
    if (::poll(&p, 1, 20) <= 0) continue;
    const ssize_t n = ::recv(fd, buffer, sizeof buffer, MSG_DONTWAIT);
    if (n == 0 || (n < 0 && errno != EAGAIN && errno != EWOULDBLOCK)) return true;
  }
  return false;
}

// A request whose head is `prefix` followed by `filler` bytes of 'a' (never ending the head),
// sent from a thread while the answer is read here: what a client that keeps sending gets.
std::string request_with_endless_head(int port, const std::string& prefix, std::size_t filler) {
  const int fd = test::connect_loopback(port);
  if (fd < 0) return "connect failed";
  std::thread sender([fd, prefix, filler] {
    send_all(fd, prefix);
    const std::string chunk(64 * 1024, 'a');
    for (std::size_t sent = 0; sent < filler; sent += chunk.size())
      if (::send(fd, chunk.data(), std::min(chunk.size(), filler - sent), MSG_NOSIGNAL) <= 0) break;
  });
  std::string answer = read_until_closed(fd, 5000);
  ::shutdown(fd, SHUT_RDWR);  // a sender still blocked in send() returns
  sender.join();
  ::close(fd);
  return answer;
}

// How long a plain GET of world.json takes, or -1 s when it does not come back 200 within 3 s.
double seconds_for_a_get(int port) {
  const auto t0 = std::chrono::steady_clock::now();
  const int status = status_of(http_get(port, "/run/world.json", 3000));
  const double s = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  return status == 200 ? s : -1.0;
}

TEST(RunServer, RequestHeadsBeyondTheLimitGet431AndNeverExhaustIt) {
  TempTree t;
  RunServer server(options_for(t));
  server.start();
  const int port = server.port();
  // 48 KiB of headers in short lines (each within cpp-httplib's own line limit), one 100 kB line,
  // and 10 MB of headers sent without pause: 431 each, read no further than the limit.
  std::string many_lines = "GET /run/world.json HTTP/1.1\r\nHost: x\r\n";
  for (int i = 0; many_lines.size() < 48 * 1024; ++i) many_lines += "X-H" + std::to_string(i) + ": " + std::string(100, 'v') + "\r\n";
  EXPECT_EQ(status_of(raw_http_request(port, many_lines + "\r\n")), 431);
  EXPECT_EQ(status_of(raw_http_request(port, "GET / HTTP/1.1\r\nX-Big: " + std::string(100000, 'a') + "\r\n\r\n")), 431);
  EXPECT_EQ(status_of(request_with_endless_head(port, "GET / HTTP/1.1\r\nX-Big: ", 10u << 20)), 431);
  // A head just within the limit is served (its lines within the 8 KiB a line may have).
  std::string within = "GET /run/world.json HTTP/1.1\r\nHost: x\r\nConnection: close\r\n";
  for (int i = 0; within.size() + 4000 < kMaxRequestHeadBytes; ++i) within += "X-Pad" + std::to_string(i) + ": " + std::string(3980, 'p') + "\r\n";
  within += "\r\n";
  EXPECT_EQ(status_of(raw_http_request(port, within)), 200) << within.size();
  // Eight clients each pushing 64 MB of one header line at once: 431 for each, and still serving.
  std::vector<std::string> answers(8);
  std::vector<std::thread> clients;
  for (std::size_t i = 0; i < answers.size(); ++i)
    clients.emplace_back([&, i] { answers[i] = request_with_endless_head(port, "GET / HTTP/1.1\r\nX-Big: ", 64u << 20); });
  for (std::thread& c : clients) c.join();
  for (const std::string& a : answers) EXPECT_EQ(status_of(a), 431);
  EXPECT_EQ(status_of(http_get(port, "/run/world.json")), 200);
}

TEST(RunServer, SlowAndIdleClientsHoldBackNoOtherClient) {
  TempTree t;
  RunServer server(options_for(t));
  server.start();
  const int port = server.port();
  // 30 clients sending their head a line at a time, a line every 200 ms (more clients than workers).
  const std::vector<int> slow = unfinished_requests(port, 30);
  std::atomic<bool> done{false};
  std::thread trickle([&] {
    for (int line = 0; !done; ++line) {
      for (const int fd : slow) send_all(fd, "X-Line-" + std::to_string(line) + ": v\r\n");
      std::this_thread::sleep_for(std::chrono::milliseconds(200));
    }
  });
  std::this_thread::sleep_for(std::chrono::milliseconds(300));
  for (int i = 0; i < 5; ++i) {
    const double s = seconds_for_a_get(port);
    EXPECT_GE(s, 0.0) << "a GET failed while 30 clients trickled their heads";
    EXPECT_LT(s, 2.0) << "a GET waited behind the slow clients";
  }
  done = true;
  trickle.join();
  for (const int fd : slow) ::close(fd);

  // 20 clients that make a keep-alive request, read the answer, then sit idle with the socket open:
  // the server closes each after its answer, and a new client is served at once.
  std::vector<int> idle;
  for (int i = 0; i < 20; ++i) {
    idle.push_back(test::connect_loopback(port));
    send_all(idle.back(), "GET /run/world.json HTTP/1.1\r\nHost: x\r\n\r\n");
  }
  for (const int fd : idle) {
    const std::string answer = read_until_closed(fd, 2000);
    EXPECT_EQ(status_of(answer), 200);
    EXPECT_NE(answer.find("Connection: close"), std::string::npos);
  }
  const double s = seconds_for_a_get(port);
  EXPECT_GE(s, 0.0);
  EXPECT_LT(s, 2.0) << "a GET waited behind idle keep-alive sockets";
  for (const int fd : idle) ::close(fd);
}

TEST(RunServer, AnUnfinishedRequestIsAnswered408AtItsDeadline) {
  TempTree t;
  RunServerOptions o = options_for(t);
  o.request_timeout_s = 0.3;
  RunServer server(o);
  server.start();
  const int fd = test::connect_loopback(server.port());
  send_all(fd, "GET /run/world.json HTTP/1.1\r\nHost: x\r\n");
  const auto t0 = std::chrono::steady_clock::now();
  const std::string answer = read_until_closed(fd, 3000);
  const double s = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  ::close(fd);
  EXPECT_EQ(status_of(answer), 408);
  EXPECT_LT(s, 2.0);
  EXPECT_EQ(status_of(http_get(server.port(), "/run/world.json")), 200);
}

TEST(RunServer, ManyUnfinishedRequestsFromOnePeerDisplaceTheOldestNotTheNewest) {
  TempTree t;
  RunServer server(options_for(t));
  server.start();
  const int port = server.port();
  // 150 clients that start a request and never finish it (more than a peer's share).
  const std::vector<int> slow = unfinished_requests(port, 150);
  ASSERT_TRUE(std::all_of(slow.begin(), slow.end(), [](int fd) { return fd >= 0; }));
  const double s = seconds_for_a_get(port);
  EXPECT_GE(s, 0.0) << "no answer while 150 requests were unfinished";
  EXPECT_LT(s, 2.0);
  // The oldest were closed to make room; the newest are still open.
  EXPECT_TRUE(closed_by_server(slow.front(), 1000));
  EXPECT_FALSE(closed_by_server(slow.back(), 100));
  for (const int fd : slow) ::close(fd);
}

TEST(RunServer, AResponseThatGoesOutTooSlowlyIsDropped) {
  TempTree t;
  t.write("run/big.bin", std::string(8u << 20, 'b'));
  RunServerOptions o = options_for(t);
  o.response_grace_s = 0.3;
  o.min_response_bytes_per_s = 16u << 20;
  RunServer server(o);
  server.start();
  // A client with a small receive buffer that reads 100 bytes every 20 ms (5 kB/s).
  const int fd = test::connect_loopback(server.port(), 4096);
  ASSERT_GE(fd, 0);
  send_all(fd, "GET /run/big.bin HTTP/1.1\r\nHost: x\r\n\r\n");
  const auto t0 = std::chrono::steady_clock::now();
  std::size_t got = 0;
  bool closed = false;
  char buffer[100];
  while (!closed && std::chrono::steady_clock::now() - t0 < std::chrono::seconds(8)) {
    std::this_thread::sleep_for(std::chrono::milliseconds(20));
    const ssize_t n = ::recv(fd, buffer, sizeof buffer, MSG_DONTWAIT);
    if (n > 0) got += static_cast<std::size_t>(n);
    else if (n == 0 || (errno != EAGAIN && errno != EWOULDBLOCK)) closed = true;
  }
  ::close(fd);
  const double s = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  EXPECT_TRUE(closed) << "still sending to a 5 kB/s reader after " << s << " s";
  EXPECT_LT(got, std::size_t{8} << 20);
  EXPECT_EQ(status_of(http_get(server.port(), "/run/world.json")), 200);
}

TEST(RunServer, APortInUseIsAnErrorNamingIt) {
  TempTree t;
  RunServer first(options_for(t));
  RunServerOptions o = options_for(t);
  o.port = first.port();
  try {
    RunServer second(o);
    FAIL() << "bound a port in use";
  } catch (const Error& e) {
    EXPECT_EQ(e.field(), "--port");
    EXPECT_NE(std::string(e.what()).find(std::to_string(first.port())), std::string::npos);
    EXPECT_NE(std::string(e.what()).find("in use"), std::string::npos);
  }
}

TEST(RunServer, AnAddressThatIsNotThisMachinesIsAnErrorNamingBind) {
  TempTree t;
  for (const char* host : {"999.1.1.1", "192.0.2.1", "not an address"}) {
    RunServerOptions o = options_for(t);
    o.host = host;
    try {
      RunServer server(o);
      FAIL() << "bound " << host;
    } catch (const Error& e) {
      EXPECT_EQ(e.field(), "--bind") << e.what();
      EXPECT_NE(std::string(e.what()).find(host), std::string::npos) << e.what();
    }
  }
}

TEST(RunServer, SaysWhetherOnlyThisMachineReachesIt) {
  TempTree t;
  RunServerOptions o = options_for(t);
  EXPECT_TRUE(RunServer(o).loopback_only());
  o.host = "127.0.0.2";
  EXPECT_TRUE(RunServer(o).loopback_only());
  o.host = "0.0.0.0";
  EXPECT_FALSE(RunServer(o).loopback_only());
}

}  // namespace
}  // namespace starnav
#endif
