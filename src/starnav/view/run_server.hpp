#pragma once
// The viewer's HTTP server (cpp-httplib): serves the viewer's files and one run folder's files,
// and, for a live run, streams its steps to every open viewer as Server-Sent Events.
//
//   GET /              the viewer (index.html)       GET /viewer.js   its bundle
//   GET /run/NAME      a file of the run: a plain name listed in run.json or set in memory
//   GET /events        the live stream (event "step": one steps.jsonl line; "end": the run ended)
// Anything else is 404; a method other than GET or HEAD 405. Only plain file names are served, and
// only when the file resolves inside the run folder (a symbolic link out of it is refused).
//
// Connections: one thread accepts every connection and reads its request (head and body) without
// blocking, under a deadline, a size limit and a limit of unfinished requests per peer; only a
// request read whole goes to cpp-httplib's request handling on a worker thread, and the
// connection closes after its response (no keep-alive). A slow or idle client thus never holds a
// worker, and one whose response goes out too slowly is dropped (docs/viewer.md, "The server").
//
// Live: publish() appends to one shared log and returns at once; each client reads the log from its
// own position on its own thread, in batches, so a slow client lags (and a stalled one is dropped
// by the write timeout) without holding back the publisher or growing memory per client.
#include <cstddef>
#include <cstdint>
#include <memory>
#include <string>

namespace starnav {

struct RunServerOptions {
  std::string run_dir;     // served under /run/ (may be empty: memory files only)
  std::string viewer_dir;  // index.html, viewer.js
  std::string host = "127.0.0.1";
  int port = 0;  // 0: any free port
  bool live = false;  // /events is served
  std::size_t max_live_clients = 32;  // more event streams get 503
  double write_timeout_s = 5.0;       // a client that takes no bytes this long is dropped
  double request_timeout_s = 10.0;    // from connecting to the whole request read: 408 after
  // A response other than the live stream is dropped when, after the grace period, it has gone
  // out slower than this on average (a client reading a byte now and then holds no worker long).
  double response_grace_s = 10.0;
  double min_response_bytes_per_s = 16.0 * 1024;
};

// What the server holds to (docs/viewer.md): the largest request head (431 beyond) and body (413
// beyond), unfinished requests per peer address and in all (the oldest is dropped for a new one),
// and requests waiting for or holding a worker (503 beyond).
inline constexpr std::size_t kMaxRequestHeadBytes = 32 * 1024;
inline constexpr std::size_t kMaxRequestBodyBytes = 64 * 1024;
inline constexpr std::size_t kMaxUnfinishedPerPeer = 64;
inline constexpr std::size_t kMaxUnfinished = 256;
inline constexpr std::size_t kMaxQueuedRequests = 256;

class RunServer {
 public:
  // Binds the socket (not yet serving). Throws Error (field "--port" or "--bind") when it cannot:
  // a port in use, a host that is not an address of this machine.
  explicit RunServer(const RunServerOptions& options);
  ~RunServer();  // stops
  RunServer(const RunServer&) = delete;
  RunServer& operator=(const RunServer&) = delete;

  int port() const;
  std::string url() const;  // http://HOST:PORT/
  // True when the bound address is a loopback one (127.0.0.0/8, ::1): only this machine reaches it.
  bool loopback_only() const;

  // Serves on a background thread until stop().
  void start();
  void stop();

  // A file served under /run/NAME from memory instead of the folder (a live run's run.json and
  // world.json before anything is written).
  void set_memory_file(const std::string& name, std::string content);
  // Appends an event for every live client (never blocks on a client).
  void publish(const std::string& event, const std::string& data);
  // Sends "end" after everything published; streams close once their clients have read it.
  void end_live();
  // Waits up to `seconds` (forever when negative) for a live client to connect (true when one has).
  bool wait_for_live_client(double seconds);
  // Waits up to `seconds` for every live client to have read everything (true when they have).
  bool wait_drained(double seconds);

  std::size_t live_clients() const;
  std::uint64_t events_published() const;

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

}  // namespace starnav
