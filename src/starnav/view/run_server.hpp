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
};

class RunServer {
 public:
  // Binds the socket (not yet serving). Throws Error (field "--port" or "--bind") when it cannot.
  explicit RunServer(const RunServerOptions& options);
  ~RunServer();  // stops
  RunServer(const RunServer&) = delete;
  RunServer& operator=(const RunServer&) = delete;

  int port() const;
  std::string url() const;  // http://HOST:PORT/

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
