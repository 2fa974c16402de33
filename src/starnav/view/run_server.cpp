#include "starnav/view/run_server.hpp"

#include <arpa/inet.h>
#include <fcntl.h>
#include <httplib.h>
#include <netdb.h>
#include <netinet/in.h>
#include <poll.h>
#include <sys/eventfd.h>
#include <sys/socket.h>
#include <unistd.h>

#include <algorithm>
#include <atomic>
#include <cctype>
#include <cerrno>
#include <chrono>
#include <condition_variable>
#include <cstring>
#include <deque>
#include <filesystem>
#include <map>
#include <mutex>
#include <string_view>
#include <thread>
#include <vector>

#include "starnav/core/error.hpp"
#include "starnav/view/run_folder.hpp"

namespace starnav {

namespace fs = std::filesystem;

namespace {

using Clock = std::chrono::steady_clock;

// Bytes per read of a served file: files stream, so a large steps.jsonl costs no memory.
constexpr std::size_t kFileChunkBytes = 64 * 1024;
// The most a live client is sent in one write (then it comes back for more).
constexpr std::size_t kEventBatchBytes = 256 * 1024;
// Workers besides the live streams: each open stream holds one worker.
constexpr std::size_t kFileThreads = 8;
// After answering an unfinished request with an error, its input is read and dropped for this long
// (or this much) before closing: closing with unread input would reset the connection and could
// destroy the answer before the client has read it.
constexpr double kDrainS = 1.0;
constexpr std::size_t kDrainBytes = 1 << 20;
// The most connections accepted in one turn of the accept loop (the unfinished ones get their turn).
constexpr int kAcceptsPerTurn = 64;

double seconds_until(Clock::time_point t) { return std::chrono::duration<double>(t - Clock::now()).count(); }

int poll_ms(double seconds) { return seconds <= 0 ? 0 : static_cast<int>(std::min(seconds * 1000.0 + 1.0, 60000.0)); }

std::string address_text(const sockaddr_storage& a, int* port) {
  char text[INET6_ADDRSTRLEN] = "";
  if (a.ss_family == AF_INET) {
    const auto& v4 = reinterpret_cast<const sockaddr_in&>(a);
    ::inet_ntop(AF_INET, &v4.sin_addr, text, sizeof text);
    if (port) *port = ntohs(v4.sin_port);
  } else if (a.ss_family == AF_INET6) {
    const auto& v6 = reinterpret_cast<const sockaddr_in6&>(a);
    ::inet_ntop(AF_INET6, &v6.sin6_addr, text, sizeof text);
    if (port) *port = ntohs(v6.sin6_port);
  }
  return text;
}

// The longest header line (cpp-httplib's own limit, which it would answer 400).
constexpr std::size_t kMaxHeaderLineBytes = 8192;

// A request's head checked before cpp-httplib sees it: the body it announces, or the status that
// refuses it. A body needs Content-Length (GET and HEAD have none; chunked bodies are not taken).
struct HeadCheck {
  int status = 0;  // 0: fine
  std::size_t body_bytes = 0;
};

bool equals_ignoring_case(std::string_view a, std::string_view b) {
  return a.size() == b.size() && std::equal(a.begin(), a.end(), b.begin(), [](char x, char y) {
           return std::tolower(static_cast<unsigned char>(x)) == std::tolower(static_cast<unsigned char>(y));
         });
}

std::string_view trimmed(std::string_view s) {
  while (!s.empty() && (s.front() == ' ' || s.front() == '\t')) s.remove_prefix(1);
  while (!s.empty() && (s.back() == ' ' || s.back() == '\t')) s.remove_suffix(1);
  return s;
}

HeadCheck check_head(std::string_view head) {
  HeadCheck check;
  bool have_length = false;
  std::size_t line_start = head.find("\r\n");
  while (line_start != std::string_view::npos && line_start + 2 < head.size()) {
    line_start += 2;
    const std::size_t line_end = head.find("\r\n", line_start);
    const std::string_view line = head.substr(line_start, line_end - line_start);
    line_start = line_end;
    if (line.size() > kMaxHeaderLineBytes) return {431, 0};
    const std::size_t colon = line.find(':');
    if (colon == std::string_view::npos) continue;  // cpp-httplib answers malformed lines
    const std::string_view name = line.substr(0, colon), value = trimmed(line.substr(colon + 1));
    if (equals_ignoring_case(name, "transfer-encoding")) return {411, 0};
    if (!equals_ignoring_case(name, "content-length")) continue;
    if (value.empty() || value.size() > 12 || !std::all_of(value.begin(), value.end(), [](char c) { return c >= '0' && c <= '9'; }))
      return {400, 0};
    const std::size_t length = std::stoul(std::string(value));
    if (have_length && length != check.body_bytes) return {400, 0};
    have_length = true;
    check.body_bytes = length;
  }
  if (check.body_bytes > kMaxRequestBodyBytes) return {413, 0};
  return check;
}

// The request's target (the second word of its first line).
std::string_view request_target(std::string_view request) {
  const std::size_t a = request.find(' ');
  if (a == std::string_view::npos) return {};
  const std::size_t b = request.find_first_of(" \r\n", a + 1);
  return request.substr(a + 1, b == std::string_view::npos ? std::string_view::npos : b - a - 1);
}

// A connection whose request has been read whole, as cpp-httplib's Stream: reads come from that
// request, writes go to the socket (non-blocking) within the write timeout per wait and, unless
// `min_rate` is 0, at no less than that average rate once `grace_s` has passed.
class ReadRequestStream final : public httplib::Stream {
 public:
  ReadRequestStream(int fd, std::string request, std::string peer, int peer_port, double write_timeout_s, double grace_s,
                    double min_rate)
      : fd_(fd), request_(std::move(request)), peer_(std::move(peer)), peer_port_(peer_port),
        write_timeout_s_(write_timeout_s), grace_s_(grace_s), min_rate_(min_rate), start_(Clock::now()) {}

  bool is_readable() const override { return read_ < request_.size(); }
  bool is_writable() const override { return wait_writable(); }

  ssize_t read(char* ptr, size_t size) override {
    const std::size_t n = std::min(size, request_.size() - read_);
    std::memcpy(ptr, request_.data() + read_, n);
    read_ += n;
    return static_cast<ssize_t>(n);
  }

  ssize_t write(const char* ptr, size_t size) override {
    std::size_t sent = 0;
    while (sent < size) {
      const ssize_t n = ::send(fd_, ptr + sent, size - sent, MSG_NOSIGNAL | MSG_DONTWAIT);
      if (n > 0) {
        sent += static_cast<std::size_t>(n);
        written_ += static_cast<std::size_t>(n);
      } else if (n < 0 && errno == EINTR) {
        continue;
      } else if (n < 0 && (errno == EAGAIN || errno == EWOULDBLOCK)) {
        if (!wait_writable()) break;
      } else {
        break;
      }
    }
    return sent == 0 && size > 0 ? -1 : static_cast<ssize_t>(sent);
  }

  void get_remote_ip_and_port(std::string& ip, int& port) const override {
    ip = peer_;
    port = peer_port_;
  }
  void get_local_ip_and_port(std::string& ip, int& port) const override {
    sockaddr_storage a{};
    socklen_t len = sizeof a;
    port = 0;
    ip = ::getsockname(fd_, reinterpret_cast<sockaddr*>(&a), &len) == 0 ? address_text(a, &port) : std::string();
  }
  socket_t socket() const override { return fd_; }

 private:
  // Waits until the socket takes bytes: at most the write timeout, and no later than the instant
  // the bytes written so far fall below the minimum rate.
  bool wait_writable() const {
    double wait = write_timeout_s_;
    if (min_rate_ > 0) {
      const auto due = start_ + std::chrono::duration_cast<Clock::duration>(
                                    std::chrono::duration<double>(grace_s_ + static_cast<double>(written_) / min_rate_));
      wait = std::min(wait, seconds_until(due));
      if (wait <= 0) return false;
    }
    pollfd p{fd_, POLLOUT, 0};
    int r = 0;
    do {
      r = ::poll(&p, 1, poll_ms(wait));
    } while (r < 0 && errno == EINTR);
    return r > 0 && (p.revents & POLLOUT) && !(p.revents & (POLLERR | POLLHUP));
  }

  int fd_;
  std::string request_;
  std::size_t read_ = 0;
  std::string peer_;
  int peer_port_;
  double write_timeout_s_, grace_s_, min_rate_;
  Clock::time_point start_;
  std::size_t written_ = 0;
};

// cpp-httplib's request handling (request line and header parsing, routing, responses, content
// providers) on requests the accept loop has read whole. Its own accept loop is not used: in
// cpp-httplib 0.11 a connection holds a pool thread from accept() on, and a header line grows
// without bound before its length is checked, so slow, idle or huge requests would starve or
// exhaust the server. process_request (protected, over any Stream) is the extension point.
class RequestHandler final : public httplib::Server {
 public:
  bool handle(httplib::Stream& stream) {
    bool closed = false;
    return process_request(stream, /*close_connection=*/true, closed, nullptr);
  }
  // Content providers run while this socket is valid (cpp-httplib's test for "shutting down").
  void set_listening_socket(int fd) { svr_sock_ = fd; }
  int take_listening_socket() { return svr_sock_.exchange(INVALID_SOCKET); }
};

// The listening socket for HOST:PORT (PORT 0: any free one). Throws Error naming --bind (not an
// address of this machine) or --port (in use, not allowed).
int listen_socket(const std::string& host, int port) {
  if (port < 0 || port > 65535) throw Error("expected a port in 0..65535, got " + std::to_string(port), "", 0, "--port");
  addrinfo hints{};
  hints.ai_family = AF_UNSPEC;
  hints.ai_socktype = SOCK_STREAM;
  hints.ai_flags = AI_PASSIVE | AI_NUMERICSERV | AI_NUMERICHOST;
  addrinfo* found = nullptr;
  const std::string service = std::to_string(port);
  int rc = ::getaddrinfo(host.c_str(), service.c_str(), &hints, &found);
  // Names (localhost) are looked up; text of digits, dots and colons that is no address is not.
  const bool name = std::any_of(host.begin(), host.end(), [](char c) { return std::isalpha(static_cast<unsigned char>(c)) != 0; }) &&
                    host.find(':') == std::string::npos;
  if (rc != 0 && name) {
    hints.ai_flags = AI_PASSIVE | AI_NUMERICSERV;
    rc = ::getaddrinfo(host.c_str(), service.c_str(), &hints, &found);
  }
  if (rc != 0 || found == nullptr)
    throw Error(name ? "cannot find the address of " + host + " (" + ::gai_strerror(rc) + ")" : "not an IP address: " + host, "", 0,
                "--bind");
  int last_error = 0;
  int fd = -1;
  for (const addrinfo* ai = found; ai != nullptr; ai = ai->ai_next) {
    fd = ::socket(ai->ai_family, ai->ai_socktype | SOCK_NONBLOCK | SOCK_CLOEXEC, ai->ai_protocol);
    if (fd < 0) {
      last_error = errno;
      continue;
    }
    // SO_REUSEADDR (a restart may bind while the last run's sockets linger), not SO_REUSEPORT,
    // with which a second server would share a port in use instead of failing.
    const int yes = 1;
    ::setsockopt(fd, SOL_SOCKET, SO_REUSEADDR, &yes, sizeof yes);
    if (::bind(fd, ai->ai_addr, ai->ai_addrlen) == 0 && ::listen(fd, 1024) == 0) break;
    last_error = errno;
    ::close(fd);
    fd = -1;
  }
  ::freeaddrinfo(found);
  if (fd >= 0) return fd;
  const std::string where = "cannot listen on " + host + ":" + std::to_string(port) + ": ";
  if (last_error == EADDRINUSE) throw Error(where + "the port is in use", "", 0, "--port");
  if (last_error == EACCES) throw Error(where + "this port needs privileges (use one above 1023)", "", 0, "--port");
  if (last_error == EADDRNOTAVAIL) throw Error(where + "not an address of this machine", "", 0, "--bind");
  throw Error(where + std::strerror(last_error), "", 0, port == 0 ? "--bind" : "--port");
}

// A connection whose request is still being read (or, after an error answer, drained).
struct Unfinished {
  int fd = -1;
  std::string peer;
  int peer_port = 0;
  std::uint64_t order = 0;  // accept order: the oldest is dropped first
  Clock::time_point deadline;
  std::string data;
  std::size_t request_bytes = 0;  // head + body once the head is whole (0 before)
  bool draining = false;
  std::size_t drained = 0;
};

const char* status_text(int status) {
  switch (status) {
    case 400: return "Bad Request";
    case 408: return "Request Timeout";
    case 411: return "Length Required";
    case 413: return "Payload Too Large";
    case 431: return "Request Header Fields Too Large";
    case 503: return "Service Unavailable";
    default: return "Error";
  }
}

}  // namespace

struct RunServer::Impl {
  RunServerOptions options;
  RequestHandler handler;
  int port = 0;
  int listen_fd = -1;
  int wake_fd = -1;
  std::thread accept_thread;
  std::unique_ptr<httplib::ThreadPool> workers;
  std::atomic<std::size_t> queued{0};  // requests waiting for or holding a worker
  std::atomic<bool> started{false};
  std::string run_dir;

  mutable std::mutex mutex;
  std::condition_variable changed;
  std::map<std::string, std::string> memory_files;
  std::deque<std::string> log;  // formatted events, in order
  bool ended = false;
  bool stopping = false;
  std::size_t clients = 0;
  std::size_t clients_behind = 0;  // clients that have not read the whole log

  // ---- the accept loop ----------------------------------------------------------------------

  std::vector<Unfinished> unfinished;
  std::uint64_t accepted = 0;

  // Removes entry i (the last one takes its place).
  void forget_unfinished(std::size_t i) {
    if (i + 1 != unfinished.size()) unfinished[i] = std::move(unfinished.back());
    unfinished.pop_back();
  }

  void close_unfinished(std::size_t i) {
    ::close(unfinished[i].fd);
    forget_unfinished(i);
  }

  // Answers an unfinished request with an error, then drains its input until the client closes.
  void refuse(Unfinished& c, int status) {
    const std::string body = std::to_string(status) + "\n";
    const std::string response = "HTTP/1.1 " + std::to_string(status) + " " + status_text(status) +
                                 "\r\nContent-Type: text/plain\r\nContent-Length: " + std::to_string(body.size()) +
                                 (status == 503 ? "\r\nRetry-After: 1" : "") + "\r\nConnection: close\r\n\r\n" + body;
    (void)::send(c.fd, response.data(), response.size(), MSG_NOSIGNAL | MSG_DONTWAIT);
    ::shutdown(c.fd, SHUT_WR);
    c.draining = true;
    c.data.clear();
    c.data.shrink_to_fit();
    c.deadline = Clock::now() + std::chrono::duration_cast<Clock::duration>(std::chrono::duration<double>(kDrainS));
  }

  void oldest_of(const std::string* peer, std::size_t& index) const {
    index = unfinished.size();
    for (std::size_t i = 0; i < unfinished.size(); ++i)
      if ((!peer || unfinished[i].peer == *peer) && (index == unfinished.size() || unfinished[i].order < unfinished[index].order))
        index = i;
  }

  void accept_connections() {
    for (int turn = 0; turn < kAcceptsPerTurn; ++turn) {
      sockaddr_storage a{};
      socklen_t len = sizeof a;
      const int fd = ::accept4(listen_fd, reinterpret_cast<sockaddr*>(&a), &len, SOCK_NONBLOCK | SOCK_CLOEXEC);
      if (fd < 0) {
        if (errno == EINTR || errno == ECONNABORTED) continue;
        if ((errno == EMFILE || errno == ENFILE) && !unfinished.empty()) {
          // Out of descriptors: the oldest unfinished request makes room.
          std::size_t oldest = 0;
          oldest_of(nullptr, oldest);
          close_unfinished(oldest);
          continue;
        }
        if (errno == EMFILE || errno == ENFILE) std::this_thread::sleep_for(std::chrono::milliseconds(10));
        return;  // EAGAIN: none left
      }
      Unfinished c;
      c.fd = fd;
      c.peer = address_text(a, &c.peer_port);
      c.order = accepted++;
      c.deadline = Clock::now() + std::chrono::duration_cast<Clock::duration>(std::chrono::duration<double>(options.request_timeout_s));
      // A new connection displaces its peer's oldest unfinished one beyond the peer's share, and
      // the oldest of all beyond the total: a slow client can hold a slot, never the server.
      const auto of_peer = static_cast<std::size_t>(
          std::count_if(unfinished.begin(), unfinished.end(), [&](const Unfinished& u) { return u.peer == c.peer; }));
      std::size_t drop = unfinished.size();
      if (of_peer >= kMaxUnfinishedPerPeer) oldest_of(&c.peer, drop);
      else if (unfinished.size() >= kMaxUnfinished) oldest_of(nullptr, drop);
      if (drop < unfinished.size()) close_unfinished(drop);
      unfinished.push_back(std::move(c));
    }
  }

  enum class Next { Keep, Close, HandedOver };

  // Reads what arrived: the connection stays unfinished, is to be closed, or went to a worker.
  Next read_some(Unfinished& c) {
    char buffer[16 * 1024];
    for (;;) {
      if (c.draining) {
        const ssize_t n = ::recv(c.fd, buffer, sizeof buffer, 0);
        if (n > 0) {
          c.drained += static_cast<std::size_t>(n);
          if (c.drained > kDrainBytes) return Next::Close;
          continue;
        }
        if (n < 0 && errno == EINTR) continue;
        return n < 0 && (errno == EAGAIN || errno == EWOULDBLOCK) ? Next::Keep : Next::Close;
      }
      const std::size_t room = kMaxRequestHeadBytes + kMaxRequestBodyBytes - c.data.size();
      const ssize_t n = ::recv(c.fd, buffer, std::min(sizeof buffer, room), 0);
      if (n == 0) return Next::Close;  // closed before its request was whole
      if (n < 0) {
        if (errno == EINTR) continue;
        return errno == EAGAIN || errno == EWOULDBLOCK ? Next::Keep : Next::Close;
      }
      const std::size_t before = c.data.size();
      c.data.append(buffer, static_cast<std::size_t>(n));
      if (c.request_bytes == 0) {
        const std::size_t end = c.data.find("\r\n\r\n", before < 3 ? 0 : before - 3);
        if (end == std::string::npos || end + 4 > kMaxRequestHeadBytes) {
          if (c.data.size() >= kMaxRequestHeadBytes) {
            refuse(c, 431);
            return Next::Keep;
          }
          continue;
        }
        const HeadCheck check = check_head(std::string_view(c.data).substr(0, end + 4));
        if (check.status != 0) {
          refuse(c, check.status);
          return Next::Keep;
        }
        c.request_bytes = end + 4 + check.body_bytes;
      }
      if (c.data.size() >= c.request_bytes) {
        c.data.resize(c.request_bytes);  // a pipelined request after it is not answered
        if (queued.load() >= kMaxQueuedRequests) {
          refuse(c, 503);
          return Next::Keep;
        }
        hand_over(c);
        return Next::HandedOver;
      }
    }
  }

  // A request read whole goes to a worker, which answers it and closes the connection.
  void hand_over(Unfinished& c) {
    ++queued;
    const double min_rate = request_target(c.data) == "/events" ? 0.0 : options.min_response_bytes_per_s;
    auto stream = std::make_shared<ReadRequestStream>(c.fd, std::move(c.data), c.peer, c.peer_port, options.write_timeout_s,
                                                      options.response_grace_s, min_rate);
    c.fd = -1;  // the worker closes it
    workers->enqueue([this, stream] {
      bool answered = false;
      try {
        answered = handler.handle(*stream);
      } catch (...) {  // a response that cannot be made drops the connection, never the server
      }
      if (answered) {
        ::shutdown(stream->socket(), SHUT_WR);
      } else {
        // Dropped (too slow, gone): reset it, or the kernel would go on sending what it holds.
        const linger reset{1, 0};
        ::setsockopt(stream->socket(), SOL_SOCKET, SO_LINGER, &reset, sizeof reset);
      }
      ::close(stream->socket());
      --queued;
    });
  }

  void accept_loop() {
    std::vector<pollfd> fds;
    for (;;) {
      {
        std::lock_guard<std::mutex> lock(mutex);
        if (stopping) break;
      }
      // Deadlines: an unfinished request is answered 408; a drained one is closed.
      const auto now = Clock::now();
      double wait = 60.0;
      for (std::size_t i = unfinished.size(); i-- > 0;) {
        Unfinished& c = unfinished[i];
        if (now >= c.deadline) {
          if (c.draining) {
            close_unfinished(i);
            continue;
          }
          refuse(c, 408);
        }
        wait = std::min(wait, seconds_until(c.deadline));
      }
      fds.clear();
      fds.push_back({wake_fd, POLLIN, 0});
      fds.push_back({listen_fd, POLLIN, 0});
      for (const Unfinished& c : unfinished) fds.push_back({c.fd, POLLIN, 0});
      const int ready = ::poll(fds.data(), fds.size(), poll_ms(wait));
      if (ready < 0) {
        if (errno == EINTR) continue;
        break;
      }
      if (fds[0].revents) {
        std::uint64_t n = 0;
        (void)::read(wake_fd, &n, sizeof n);
      }
      // Backwards: closing swaps the last entry (already seen) into the closed one's place.
      for (std::size_t i = unfinished.size(); i-- > 0;) {
        if (fds[i + 2].revents == 0) continue;
        const Next next = read_some(unfinished[i]);
        if (next == Next::Close) {
          close_unfinished(i);
        } else if (next == Next::HandedOver) {  // the worker owns the socket now
          forget_unfinished(i);
        }
      }
      if (fds[1].revents & POLLIN) accept_connections();
    }
    while (!unfinished.empty()) close_unfinished(unfinished.size() - 1);
  }

  // ---- the routes -----------------------------------------------------------------------------

  // Streams a file of the run (the RunFile rule) or of the viewer (which may be a link, e.g. into
  // a build tree) from disk in chunks.
  static void serve_file(const std::string& dir, const std::string& name, httplib::Response& res,
                         RunFile::Links links = RunFile::Links::Refuse) {
    auto file = std::make_shared<RunFile>(dir, name, links);
    if (!file->is_open()) {
      res.status = 404;
      return;
    }
    res.set_header("Cache-Control", "no-store");
    res.set_header("X-Content-Type-Options", "nosniff");
    res.set_content_provider(static_cast<std::size_t>(file->size()), content_type_of(name),
                             [file](std::size_t offset, std::size_t length, httplib::DataSink& sink) {
                               std::string buffer(std::min(length, kFileChunkBytes), '\0');
                               const std::size_t got = file->read_at(offset, buffer.data(), buffer.size());
                               if (got == 0) return false;
                               return sink.write(buffer.data(), got);
                             });
  }

  // A file of the run by name, from memory or the folder, or 404.
  void serve_run_file(const std::string& name, httplib::Response& res) {
    if (!is_plain_file_name(name)) {
      res.status = 404;
      return;
    }
    {
      std::lock_guard<std::mutex> lock(mutex);
      if (const auto it = memory_files.find(name); it != memory_files.end()) {
        res.set_header("Cache-Control", "no-store");
        res.set_content(it->second, content_type_of(name).c_str());
        return;
      }
    }
    if (run_dir.empty()) {
      res.status = 404;
      return;
    }
    serve_file(run_dir, name, res);
  }

  void serve_events(httplib::Response& res) {
    {
      std::lock_guard<std::mutex> lock(mutex);
      if (clients >= options.max_live_clients) {
        res.status = 503;
        res.set_content("too many live viewers\n", "text/plain");
        return;
      }
      ++clients;
      ++clients_behind;
    }
    changed.notify_all();
    res.set_header("Cache-Control", "no-cache");
    res.set_header("X-Accel-Buffering", "no");
    auto position = std::make_shared<std::size_t>(0);
    auto finished = std::make_shared<bool>(false);
    res.set_chunked_content_provider(
        "text/event-stream",
        [this, position, finished](std::size_t, httplib::DataSink& sink) {
          std::string batch;
          bool end = false;
          {
            std::unique_lock<std::mutex> lock(mutex);
            changed.wait_for(lock, std::chrono::seconds(1), [&] { return stopping || *position < log.size() || ended; });
            if (stopping) return false;
            while (*position < log.size() && batch.size() < kEventBatchBytes) batch += log[(*position)++];
            if (*position == log.size() && ended) end = true;
          }
          if (batch.empty() && !end) batch = ": keep-alive\n\n";
          if (!batch.empty() && !sink.write(batch.data(), batch.size())) return false;
          if (end) {
            {
              std::lock_guard<std::mutex> lock(mutex);
              if (!*finished) {
                *finished = true;
                --clients_behind;
              }
            }
            changed.notify_all();
            sink.done();
          }
          return true;
        },
        [this, finished](bool) {
          {
            std::lock_guard<std::mutex> lock(mutex);
            --clients;
            if (!*finished) --clients_behind;
          }
          changed.notify_all();
        });
  }
};

RunServer::RunServer(const RunServerOptions& options) : impl_(std::make_unique<Impl>()) {
  Impl& s = *impl_;
  s.options = options;
  if (!(options.request_timeout_s > 0) || !(options.write_timeout_s > 0) || !(options.response_grace_s >= 0) ||
      !(options.min_response_bytes_per_s >= 0))
    throw Error("the server's timeouts must be positive and its minimum rate not negative", "", 0, "timeout");
  if (!options.run_dir.empty()) {
    std::error_code ec;
    s.run_dir = fs::canonical(options.run_dir, ec).string();
    if (ec) throw Error("cannot open the run folder: " + ec.message(), options.run_dir, 0, "RUN_DIR");
  }
  httplib::Server& h = s.handler;
  h.set_payload_max_length(kMaxRequestBodyBytes);
  const std::string viewer = options.viewer_dir;
  const auto viewer_file = [viewer](const std::string& name) {
    return [viewer, name](const httplib::Request&, httplib::Response& res) {
      Impl::serve_file(viewer, name, res, RunFile::Links::Follow);
    };
  };
  h.Get("/", viewer_file("index.html"));
  h.Get("/index.html", viewer_file("index.html"));
  h.Get("/viewer.js", viewer_file("viewer.js"));
  h.Get(R"(/run/([^/]+))", [this](const httplib::Request& req, httplib::Response& res) {
    impl_->serve_run_file(req.matches[1].str(), res);
  });
  if (options.live) h.Get("/events", [this](const httplib::Request&, httplib::Response& res) { impl_->serve_events(res); });
  const auto not_allowed = [](const httplib::Request&, httplib::Response& res) {
    res.status = 405;
    res.set_header("Allow", "GET, HEAD");
  };
  h.Post(R"(/.*)", not_allowed);
  h.Put(R"(/.*)", not_allowed);
  h.Delete(R"(/.*)", not_allowed);
  h.Patch(R"(/.*)", not_allowed);
  h.Options(R"(/.*)", not_allowed);
  h.set_error_handler([](const httplib::Request&, httplib::Response& res) {
    if (res.body.empty()) res.set_content(std::to_string(res.status) + "\n", "text/plain");
  });

  s.listen_fd = listen_socket(options.host, options.port);
  sockaddr_storage bound{};
  socklen_t len = sizeof bound;
  ::getsockname(s.listen_fd, reinterpret_cast<sockaddr*>(&bound), &len);
  address_text(bound, &s.port);
  s.handler.set_listening_socket(s.listen_fd);
  s.wake_fd = ::eventfd(0, EFD_NONBLOCK | EFD_CLOEXEC);
  if (s.wake_fd < 0) {
    ::close(s.listen_fd);
    throw Error(std::string("cannot make the server's wake-up event: ") + std::strerror(errno), "", 0, "");
  }
}

RunServer::~RunServer() {
  stop();
  if (impl_->wake_fd >= 0) ::close(impl_->wake_fd);
}

int RunServer::port() const { return impl_->port; }

std::string RunServer::url() const {
  const std::string& host = impl_->options.host;
  const bool v6 = host.find(':') != std::string::npos;
  return "http://" + (v6 ? "[" + host + "]" : host) + ":" + std::to_string(impl_->port) + "/";
}

bool RunServer::loopback_only() const {
  sockaddr_storage a{};
  socklen_t len = sizeof a;
  if (impl_->listen_fd < 0 || ::getsockname(impl_->listen_fd, reinterpret_cast<sockaddr*>(&a), &len) != 0) return false;
  if (a.ss_family == AF_INET) return (ntohl(reinterpret_cast<const sockaddr_in&>(a).sin_addr.s_addr) >> 24) == 127;
  if (a.ss_family != AF_INET6) return false;
  const in6_addr& v6 = reinterpret_cast<const sockaddr_in6&>(a).sin6_addr;
  return IN6_IS_ADDR_LOOPBACK(&v6) || (IN6_IS_ADDR_V4MAPPED(&v6) && v6.s6_addr[12] == 127);
}

void RunServer::start() {
  Impl& s = *impl_;
  if (s.started.exchange(true)) return;
  s.workers = std::make_unique<httplib::ThreadPool>(kFileThreads + (s.options.live ? s.options.max_live_clients : 0));
  s.accept_thread = std::thread([&s] { s.accept_loop(); });
}

void RunServer::stop() {
  Impl& s = *impl_;
  {
    std::lock_guard<std::mutex> lock(s.mutex);
    if (s.stopping) return;
    s.stopping = true;
  }
  s.changed.notify_all();
  // Content providers stop once the listening socket is gone (cpp-httplib's shutdown test).
  const int fd = s.handler.take_listening_socket();
  const std::uint64_t one = 1;
  (void)::write(s.wake_fd, &one, sizeof one);
  if (s.accept_thread.joinable()) s.accept_thread.join();
  if (s.workers) s.workers->shutdown();
  if (fd >= 0) ::close(fd);
  s.listen_fd = -1;
}

void RunServer::set_memory_file(const std::string& name, std::string content) {
  std::lock_guard<std::mutex> lock(impl_->mutex);
  impl_->memory_files[name] = std::move(content);
}

void RunServer::publish(const std::string& event, const std::string& data) {
  std::string text = "event: " + event + "\n";
  // One data line per line of the payload (SSE).
  for (std::size_t start = 0; start <= data.size();) {
    const std::size_t nl = data.find('\n', start);
    const std::size_t end = nl == std::string::npos ? data.size() : nl;
    text += "data: " + data.substr(start, end - start) + "\n";
    if (nl == std::string::npos) break;
    start = nl + 1;
  }
  text += "\n";
  {
    std::lock_guard<std::mutex> lock(impl_->mutex);
    impl_->log.push_back(std::move(text));
  }
  impl_->changed.notify_all();
}

void RunServer::end_live() {
  publish("end", "{}");
  {
    std::lock_guard<std::mutex> lock(impl_->mutex);
    impl_->ended = true;
  }
  impl_->changed.notify_all();
}

bool RunServer::wait_for_live_client(double seconds) {
  std::unique_lock<std::mutex> lock(impl_->mutex);
  const auto connected = [this] { return impl_->clients > 0 || impl_->stopping; };
  if (seconds < 0) {
    impl_->changed.wait(lock, connected);
  } else {
    impl_->changed.wait_for(lock, std::chrono::duration<double>(seconds), connected);
  }
  return impl_->clients > 0;
}

bool RunServer::wait_drained(double seconds) {
  std::unique_lock<std::mutex> lock(impl_->mutex);
  return impl_->changed.wait_for(lock, std::chrono::duration<double>(seconds), [this] { return impl_->clients_behind == 0; });
}

std::size_t RunServer::live_clients() const {
  std::lock_guard<std::mutex> lock(impl_->mutex);
  return impl_->clients;
}

std::uint64_t RunServer::events_published() const {
  std::lock_guard<std::mutex> lock(impl_->mutex);
  return impl_->log.size();
}

}  // namespace starnav
