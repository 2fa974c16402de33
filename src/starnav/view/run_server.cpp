#include "starnav/view/run_server.hpp"

#include <httplib.h>

#include <chrono>
#include <condition_variable>
#include <deque>
#include <filesystem>
#include <fstream>
#include <map>
#include <mutex>
#include <thread>

#include "starnav/core/error.hpp"
#include "starnav/view/run_folder.hpp"

namespace starnav {

namespace fs = std::filesystem;

namespace {

// Bytes per read of a served file: files stream, so a large steps.jsonl costs no memory.
constexpr std::size_t kFileChunkBytes = 64 * 1024;
// The most a live client is sent in one write (then it comes back for more).
constexpr std::size_t kEventBatchBytes = 256 * 1024;
// Threads besides the live streams: each open stream holds one of cpp-httplib's pool threads.
constexpr std::size_t kFileThreads = 8;

// Streams a file from disk in chunks.
void serve_file(const fs::path& path, const std::string& type, httplib::Response& res) {
  std::error_code ec;
  const std::uintmax_t size = fs::file_size(path, ec);
  if (ec) {
    res.status = 404;
    return;
  }
  auto in = std::make_shared<std::ifstream>(path, std::ios::binary);
  if (!*in) {
    res.status = 404;
    return;
  }
  res.set_header("Cache-Control", "no-store");
  res.set_header("X-Content-Type-Options", "nosniff");
  res.set_content_provider(static_cast<std::size_t>(size), type, [in](std::size_t offset, std::size_t length, httplib::DataSink& sink) {
    std::string buffer(std::min(length, kFileChunkBytes), '\0');
    in->seekg(static_cast<std::streamoff>(offset));
    in->read(buffer.data(), static_cast<std::streamsize>(buffer.size()));
    const auto got = static_cast<std::size_t>(in->gcount());
    if (got == 0) return false;
    return sink.write(buffer.data(), got);
  });
}

}  // namespace

struct RunServer::Impl {
  RunServerOptions options;
  httplib::Server server;
  int port = 0;
  std::thread thread;
  fs::path run_root;  // canonical run folder

  mutable std::mutex mutex;
  std::condition_variable changed;
  std::map<std::string, std::string> memory_files;
  std::deque<std::string> log;  // formatted events, in order
  bool ended = false;
  bool stopping = false;
  std::size_t clients = 0;
  std::size_t clients_behind = 0;  // clients that have not read the whole log

  // A file of the run by name, or 404.
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
    if (run_root.empty()) {
      res.status = 404;
      return;
    }
    std::error_code ec;
    const fs::path path = fs::canonical(run_root / name, ec);
    // Only a regular file that resolves inside the folder itself.
    if (ec || path.parent_path() != run_root || !fs::is_regular_file(path, ec)) {
      res.status = 404;
      return;
    }
    serve_file(path, content_type_of(name), res);
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
  if (!options.run_dir.empty()) {
    std::error_code ec;
    s.run_root = fs::canonical(options.run_dir, ec);
    if (ec) throw Error("cannot open the run folder: " + ec.message(), options.run_dir, 0, "RUN_DIR");
  }
  const std::size_t threads = kFileThreads + (options.live ? options.max_live_clients : 0);
  s.server.new_task_queue = [threads] { return new httplib::ThreadPool(threads); };
  const auto timeout = std::chrono::duration<double>(options.write_timeout_s);
  s.server.set_write_timeout(std::chrono::duration_cast<std::chrono::microseconds>(timeout));
  s.server.set_read_timeout(std::chrono::seconds(5));
  s.server.set_payload_max_length(64 * 1024);
  // SO_REUSEADDR (a restart may bind while the last run's sockets linger) but not cpp-httplib's
  // default SO_REUSEPORT, with which a second server would share a port in use instead of failing.
  s.server.set_socket_options([](socket_t sock) {
    int yes = 1;
    setsockopt(sock, SOL_SOCKET, SO_REUSEADDR, &yes, sizeof yes);
  });
  s.server.set_keep_alive_max_count(100);

  const fs::path viewer(options.viewer_dir);
  s.server.Get("/", [viewer](const httplib::Request&, httplib::Response& res) {
    serve_file(viewer / "index.html", content_type_of("index.html"), res);
  });
  s.server.Get("/index.html", [viewer](const httplib::Request&, httplib::Response& res) {
    serve_file(viewer / "index.html", content_type_of("index.html"), res);
  });
  s.server.Get("/viewer.js", [viewer](const httplib::Request&, httplib::Response& res) {
    serve_file(viewer / "viewer.js", content_type_of("viewer.js"), res);
  });
  s.server.Get(R"(/run/([^/]+))", [this](const httplib::Request& req, httplib::Response& res) {
    impl_->serve_run_file(req.matches[1].str(), res);
  });
  if (options.live)
    s.server.Get("/events", [this](const httplib::Request&, httplib::Response& res) { impl_->serve_events(res); });
  const auto not_allowed = [](const httplib::Request&, httplib::Response& res) {
    res.status = 405;
    res.set_header("Allow", "GET, HEAD");
  };
  for (const char* pattern : {R"(/.*)"}) {
    s.server.Post(pattern, not_allowed);
    s.server.Put(pattern, not_allowed);
    s.server.Delete(pattern, not_allowed);
    s.server.Patch(pattern, not_allowed);
    s.server.Options(pattern, not_allowed);
  }
  s.server.set_error_handler([](const httplib::Request&, httplib::Response& res) {
    if (res.body.empty()) res.set_content(std::to_string(res.status) + "\n", "text/plain");
  });

  if (options.port < 0 || options.port > 65535)
    throw Error("expected a port in 0..65535, got " + std::to_string(options.port), "", 0, "--port");
  s.port = options.port == 0 ? s.server.bind_to_any_port(options.host) : (s.server.bind_to_port(options.host, options.port) ? options.port : -1);
  if (s.port <= 0)
    throw Error("cannot listen on " + options.host + ":" + std::to_string(options.port) +
                    " (in use, or not an address of this machine)",
                "", 0, options.port == 0 ? "--bind" : "--port");
}

RunServer::~RunServer() { stop(); }

int RunServer::port() const { return impl_->port; }

std::string RunServer::url() const {
  const std::string& host = impl_->options.host;
  const bool v6 = host.find(':') != std::string::npos;
  return "http://" + (v6 ? "[" + host + "]" : host) + ":" + std::to_string(impl_->port) + "/";
}

void RunServer::start() {
  if (impl_->thread.joinable()) return;
  impl_->thread = std::thread([this] { impl_->server.listen_after_bind(); });
  // Requests made right after start() must find it listening.
  while (!impl_->server.is_running()) std::this_thread::sleep_for(std::chrono::milliseconds(1));
}

void RunServer::stop() {
  {
    std::lock_guard<std::mutex> lock(impl_->mutex);
    impl_->stopping = true;
  }
  impl_->changed.notify_all();
  impl_->server.stop();
  if (impl_->thread.joinable()) impl_->thread.join();
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
