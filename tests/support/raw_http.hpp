#pragma once
// HTTP over a plain loopback socket, for the server tests: the request's bytes exactly as given
// (malformed ones too), and everything the server answers until it closes the connection.
#include <arpa/inet.h>
#include <netinet/in.h>
#include <sys/socket.h>
#include <unistd.h>

#include <cstdint>
#include <string>

namespace starnav::test {

// A socket connected to 127.0.0.1:port (-1 when nothing listens); `receive_buffer` bytes of
// receive buffer when positive (a client that reads slowly or not at all).
inline int connect_loopback(int port, int receive_buffer = 0) {
  const int fd = ::socket(AF_INET, SOCK_STREAM, 0);
  if (receive_buffer > 0) ::setsockopt(fd, SOL_SOCKET, SO_RCVBUF, &receive_buffer, sizeof receive_buffer);
  sockaddr_in addr{};
  addr.sin_family = AF_INET;
  addr.sin_port = htons(static_cast<std::uint16_t>(port));
  addr.sin_addr.s_addr = htonl(INADDR_LOOPBACK);
  if (::connect(fd, reinterpret_cast<sockaddr*>(&addr), sizeof addr) != 0) {
    ::close(fd);
    return -1;
  }
  return fd;
}

// Sends `request` to 127.0.0.1:port and returns the answer, read until the server closes or no
// byte arrives for `timeout_ms`; "connect failed" when nothing listens.
inline std::string raw_http_request(int port, const std::string& request, int timeout_ms = 3000) {
  const int fd = connect_loopback(port);
  if (fd < 0) return "connect failed";
  timeval tv{timeout_ms / 1000, (timeout_ms % 1000) * 1000};
  ::setsockopt(fd, SOL_SOCKET, SO_RCVTIMEO, &tv, sizeof tv);
  (void)::send(fd, request.data(), request.size(), MSG_NOSIGNAL);
  std::string out;
  char buffer[65536];
  for (ssize_t n; (n = ::recv(fd, buffer, sizeof buffer, 0)) > 0;) out.append(buffer, static_cast<std::size_t>(n));
  ::close(fd);
  return out;
}

// GET `target` with Connection: close.
inline std::string http_get(int port, const std::string& target, int timeout_ms = 3000) {
  return raw_http_request(port, "GET " + target + " HTTP/1.1\r\nHost: 127.0.0.1\r\nConnection: close\r\n\r\n", timeout_ms);
}

}  // namespace starnav::test
