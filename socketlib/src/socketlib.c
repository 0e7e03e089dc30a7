/* TCP with deadlines. See socketlib.h for the contract of each call.
 *
 * POSIX sockets, or Winsock on Windows (the FMU's win64 DLL): the few calls
 * that differ are mapped just below, so each function reads the same on both. */
#define _GNU_SOURCE /* accept4, SOCK_CLOEXEC */
#include "socketlib/socketlib.h"

#include <errno.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#ifdef _WIN32
/* Winsock: a SOCKET is a small handle that fits our int (INVALID_SOCKET
 * casts to -1); the calls take char* buffers and int lengths; errors come
 * from WSAGetLastError(). poll() is emulated with select(), which (unlike
 * WSAPoll on Windows before 10 2004) reports a refused non-blocking connect. */
#define FD_SETSIZE 4096
#ifndef _WIN32_WINNT
#define _WIN32_WINNT 0x0601 /* Windows 7: inet_ntop, GetTickCount64 */
#endif
#include <winsock2.h>
#include <ws2tcpip.h>
#include <windows.h>
typedef unsigned long nfds_t;
#define pollfd sl__pollfd /* winsock2.h has its own, with a SOCKET; its POLL* bits are kept */
struct pollfd {
  int fd;
  short events, revents;
};
#define SL__EINTR WSAEINTR
#define SL__EAGAIN WSAEWOULDBLOCK
#define SL__EINPROGRESS WSAEWOULDBLOCK
#define SL__ECONNREFUSED WSAECONNREFUSED
#define SL__ECONNRESET WSAECONNRESET
#define SL__ECONNABORTED WSAECONNABORTED
#define SL__EPIPE WSAESHUTDOWN
#define SL__SOCK_FLAGS 0
#define SL__MSG_SEND 0
#define SL__MSG_RECV 0
static int sl__errno(void) { return WSAGetLastError(); }
static int sl__close_fd(int fd) { return closesocket((SOCKET)fd); }
static int sl__set_nonblocking(int fd) {
  u_long on = 1;
  return ioctlsocket((SOCKET)fd, FIONBIO, &on) == 0 ? 0 : -1;
}
/* Winsock is started once per process, by the first call that needs it. */
static void sl__startup(void) {
  static LONG started = 0;
  if (InterlockedCompareExchange(&started, 1, 0) == 0) {
    WSADATA data;
    WSAStartup(MAKEWORD(2, 2), &data);
  }
}
static int poll(struct pollfd *p, nfds_t n, int timeout_ms) {
  fd_set rd, wr, ex;
  FD_ZERO(&rd);
  FD_ZERO(&wr);
  FD_ZERO(&ex);
  for (nfds_t i = 0; i < n; ++i) {
    if (p[i].events & POLLIN) FD_SET((SOCKET)p[i].fd, &rd);
    if (p[i].events & POLLOUT) FD_SET((SOCKET)p[i].fd, &wr);
    FD_SET((SOCKET)p[i].fd, &ex);
  }
  struct timeval tv = {timeout_ms / 1000, (timeout_ms % 1000) * 1000};
  int r = select(0, &rd, &wr, &ex, &tv);
  if (r <= 0) return r == 0 ? 0 : -1;
  int count = 0;
  for (nfds_t i = 0; i < n; ++i) {
    p[i].revents = 0;
    if (FD_ISSET((SOCKET)p[i].fd, &rd)) p[i].revents |= POLLIN;
    if (FD_ISSET((SOCKET)p[i].fd, &wr)) p[i].revents |= POLLOUT;
    if (FD_ISSET((SOCKET)p[i].fd, &ex)) p[i].revents |= POLLERR;
    count += p[i].revents != 0;
  }
  return count;
}
static void sl__sleep_ms(long ms) { Sleep((DWORD)ms); }
static int accept4(int fd, struct sockaddr *a, socklen_t *len, int flags) {
  (void)flags;
  SOCKET c = accept((SOCKET)fd, a, len);
  if (c == INVALID_SOCKET) return -1;
  if (sl__set_nonblocking((int)c) != 0) {
    closesocket(c);
    return -1;
  }
  return (int)c;
}
#define SOCK_CLOEXEC 0
#define SOCK_NONBLOCK 0
#else
#include <arpa/inet.h>
#include <fcntl.h>
#include <netdb.h>
#include <netinet/in.h>
#include <netinet/tcp.h>
#include <poll.h>
#include <sys/socket.h>
#include <time.h>
#include <unistd.h>
#define SL__EINTR EINTR
#define SL__EAGAIN EAGAIN
#define SL__EINPROGRESS EINPROGRESS
#define SL__ECONNREFUSED ECONNREFUSED
#define SL__ECONNRESET ECONNRESET
#define SL__ECONNABORTED ECONNABORTED
#define SL__EPIPE EPIPE
#define SL__SOCK_FLAGS SOCK_CLOEXEC
#define SL__MSG_SEND (MSG_NOSIGNAL | MSG_DONTWAIT)
#define SL__MSG_RECV MSG_DONTWAIT
static int sl__errno(void) { return errno; }
static int sl__close_fd(int fd) { return close(fd); }
static int sl__set_nonblocking(int fd) {
  int flags = fcntl(fd, F_GETFL, 0);
  if (flags < 0) return -1;
  return fcntl(fd, F_SETFL, flags | O_NONBLOCK);
}
static void sl__startup(void) {}
static void sl__sleep_ms(long ms) {
  struct timespec pause = {ms / 1000, (ms % 1000) * 1000000L};
  nanosleep(&pause, NULL);
}
#endif

/* Pause between connection attempts while the server is not yet listening. */
#define SL__CONNECT_RETRY_MS 50

const char *sl_strerror(int code) {
  switch (code) {
    case SL_OK:
      return "success";
#define SL__MSG(name, value, msg) \
  case value:                     \
    return msg;
    SL_ERRNO_MAP(SL__MSG)
#undef SL__MSG
  }
  return "unknown socketlib error";
}

const char *sl_err_name(int code) {
  switch (code) {
    case SL_OK:
      return "SL_OK";
#define SL__NAME(name, value, msg) \
  case value:                      \
    return "SL_E" #name;
    SL_ERRNO_MAP(SL__NAME)
#undef SL__NAME
  }
  return "SL_E?";
}

int64_t sl_now_ms(void) {
#ifdef _WIN32
  return (int64_t)GetTickCount64();
#else
  struct timespec ts;
  clock_gettime(CLOCK_MONOTONIC, &ts);
  return (int64_t)ts.tv_sec * 1000 + ts.tv_nsec / 1000000;
#endif
}

static int sl__sys(sl_socket *s, int err) {
  if (s) s->sys_errno = err;
  return SL_ESYSTEM;
}

static const volatile sig_atomic_t *sl__stop_flag = NULL;

void sl_set_stop_flag(const volatile sig_atomic_t *flag) { sl__stop_flag = flag; }
const volatile sig_atomic_t *sl_get_stop_flag(void) { return sl__stop_flag; }

static int sl__stopping(void) { return sl__stop_flag && *sl__stop_flag; }

/* Milliseconds left until the deadline, clamped to poll()'s range. */
static int sl__remaining(int64_t deadline_ms) {
  int64_t left = deadline_ms - sl_now_ms();
  if (left <= 0) return 0;
  if (left > 1000000000) return 1000000000;
  return (int)left;
}

/* How long one poll() may sleep: to the deadline, but with a stop flag at
 * most 200 ms, so a signal that lands just before poll() is seen soon. */
static int sl__slice(int64_t deadline_ms) {
  int left = sl__remaining(deadline_ms);
  return (sl__stop_flag && left > 200) ? 200 : left;
}

/* poll() the n entries of p until one is ready or the deadline passes:
 * restarted after a signal or an early wake, in slices of at most 200 ms when
 * a stop flag is set (sl__slice), returning SL_EINTERRUPTED once it is.
 * Returns how many are ready (> 0), 0 at the deadline, <0 error (errno kept
 * in s->sys_errno). */
static int sl__poll(struct pollfd *p, nfds_t n, int64_t deadline_ms, sl_socket *s) {
  for (;;) {
    if (sl__stopping()) return SL_EINTERRUPTED;
    for (nfds_t i = 0; i < n; ++i) p[i].revents = 0;
    int r = poll(p, n, sl__slice(deadline_ms));
    if (r > 0) return r;
    if (r == 0) {
      if (sl__remaining(deadline_ms) > 0) continue; /* a slice ended, or woke a little early */
      return 0;
    }
    if (sl__errno() == SL__EINTR) continue; /* the loop's head looks at the stop flag */
    return sl__sys(s, sl__errno());
  }
}

/* Wait until fd is ready for events or the deadline passes.
 * Returns 1 ready, 0 timed out, <0 error. */
static int sl__wait(sl_socket *s, short events, int64_t deadline_ms) {
  struct pollfd p;
  p.fd = s->fd;
  p.events = events;
  int r = sl__poll(&p, 1, deadline_ms, s);
  return r > 0 ? 1 : r;
}

int sl_parse_endpoint(const char *endpoint, char *host_out, size_t host_cap, int *port_out) {
  if (!endpoint || !host_out || host_cap == 0 || !port_out) return SL_EINVAL;
  const char *colon;
  const char *host_begin = endpoint;
  size_t host_len;
  if (endpoint[0] == '[') { /* [IPv6]:port */
    const char *close = strchr(endpoint, ']');
    if (!close || close[1] != ':') return SL_EADDRESS;
    host_begin = endpoint + 1;
    host_len = (size_t)(close - host_begin);
    colon = close + 1;
  } else {
    colon = strrchr(endpoint, ':');
    if (!colon) return SL_EADDRESS;
    host_len = (size_t)(colon - endpoint);
  }
  if (host_len == 0 || host_len >= host_cap) return SL_EADDRESS;
  char *end = NULL;
  errno = 0;
  long port = strtol(colon + 1, &end, 10);
  if (errno != 0 || end == colon + 1 || *end != '\0' || port < 0 || port > 65535)
    return SL_EADDRESS;
  memcpy(host_out, host_begin, host_len);
  host_out[host_len] = '\0';
  *port_out = (int)port;
  return SL_OK;
}

static int sl__resolve(const char *host, int port, int passive, struct addrinfo **out) {
  sl__startup();
  char service[16];
  snprintf(service, sizeof service, "%d", port);
  struct addrinfo hints;
  memset(&hints, 0, sizeof hints);
  hints.ai_family = AF_UNSPEC;
  hints.ai_socktype = SOCK_STREAM;
  hints.ai_flags = AI_NUMERICSERV | (passive ? AI_PASSIVE : 0);
  return getaddrinfo(host, service, &hints, out) == 0 ? SL_OK : SL_EADDRESS;
}

static void sl__tune(int fd) {
  int one = 1;
  setsockopt(fd, IPPROTO_TCP, TCP_NODELAY, (const char *)&one, sizeof one);
#ifdef SO_NOSIGPIPE
  setsockopt(fd, SOL_SOCKET, SO_NOSIGPIPE, &one, sizeof one);
#endif
}

int sl_listen(const char *host, int port, sl_socket *out) {
  if (!host || !out || port < 0 || port > 65535) return SL_EINVAL;
  out->fd = -1;
  out->sys_errno = 0;
  struct addrinfo *ai = NULL;
  int rc = sl__resolve(host, port, 1, &ai);
  if (rc != SL_OK) return rc;
  rc = SL_EADDRESS;
  for (struct addrinfo *a = ai; a; a = a->ai_next) {
    int fd = (int)socket(a->ai_family, a->ai_socktype | SL__SOCK_FLAGS, a->ai_protocol);
    if (fd < 0) {
      rc = sl__sys(out, sl__errno());
      continue;
    }
    int one = 1;
#ifndef _WIN32 /* on Windows SO_REUSEADDR would let another process bind the same port; without it a port in use is refused, as here */
    setsockopt(fd, SOL_SOCKET, SO_REUSEADDR, &one, sizeof one);
#else
    (void)one;
#endif
    if (bind(fd, a->ai_addr, a->ai_addrlen) == 0 && listen(fd, 64) == 0 &&
        sl__set_nonblocking(fd) == 0) {
      out->fd = fd;
      rc = SL_OK;
      break;
    }
    rc = sl__sys(out, sl__errno());
    sl__close_fd(fd);
  }
  freeaddrinfo(ai);
  return rc;
}

int sl_local_port(const sl_socket *s) {
  struct sockaddr_storage ss;
  socklen_t len = sizeof ss;
  if (!s || s->fd < 0 || getsockname(s->fd, (struct sockaddr *)&ss, &len) != 0) return SL_EINVAL;
  if (ss.ss_family == AF_INET) return ntohs(((struct sockaddr_in *)&ss)->sin_port);
  if (ss.ss_family == AF_INET6) return ntohs(((struct sockaddr_in6 *)&ss)->sin6_port);
  return SL_EINVAL;
}

int sl_accept(sl_socket *listener, int64_t deadline_ms, sl_socket *out) {
  if (!listener || listener->fd < 0 || !out) return SL_EINVAL;
  out->fd = -1;
  out->sys_errno = 0;
  for (;;) {
    int w = sl__wait(listener, POLLIN, deadline_ms);
    if (w < 0) return w;
    if (w == 0) return SL_ETIMEDOUT;
    int fd = accept4(listener->fd, NULL, NULL, SOCK_CLOEXEC | SOCK_NONBLOCK);
    if (fd >= 0) {
      sl__tune(fd);
      out->fd = fd;
      return SL_OK;
    }
    const int e = sl__errno();
    if (e == SL__EAGAIN || e == SL__EINTR || e == SL__ECONNABORTED) continue;
    return sl__sys(listener, e);
  }
}

/* One connection attempt. SL_OK, SL_EREFUSED (try again), SL_ETIMEDOUT or error. */
static int sl__connect_once(const struct addrinfo *a, int64_t deadline_ms, sl_socket *out) {
  int fd = (int)socket(a->ai_family, a->ai_socktype | SL__SOCK_FLAGS | SOCK_NONBLOCK, a->ai_protocol);
  if (fd < 0) return sl__sys(out, sl__errno());
#ifdef _WIN32
  if (sl__set_nonblocking(fd) != 0) {
    const int e = sl__errno();
    sl__close_fd(fd);
    return sl__sys(out, e);
  }
#endif
  out->fd = fd;
  int rc;
  int e = 0;
  if (connect(fd, a->ai_addr, (socklen_t)a->ai_addrlen) == 0) {
    rc = SL_OK;
  } else if ((e = sl__errno()) == SL__EINPROGRESS) {
    int w = sl__wait(out, POLLOUT, deadline_ms);
    if (w < 0) {
      rc = w;
    } else if (w == 0) {
      rc = SL_ETIMEDOUT;
    } else {
      int err = 0;
      socklen_t len = sizeof err;
      getsockopt(fd, SOL_SOCKET, SO_ERROR, (char *)&err, &len);
      rc = err == 0 ? SL_OK : (err == SL__ECONNREFUSED ? SL_EREFUSED : sl__sys(out, err));
    }
  } else {
    rc = e == SL__ECONNREFUSED ? SL_EREFUSED : sl__sys(out, e);
  }
  if (rc != SL_OK) {
    sl__close_fd(fd);
    out->fd = -1;
  }
  return rc;
}

int sl_connect(const char *host, int port, int64_t deadline_ms, sl_socket *out) {
  if (!host || !out || port <= 0 || port > 65535) return SL_EINVAL;
  out->fd = -1;
  out->sys_errno = 0;
  struct addrinfo *ai = NULL;
  int rc = sl__resolve(host, port, 0, &ai);
  if (rc != SL_OK) return rc;
  for (;;) {
    for (struct addrinfo *a = ai; a; a = a->ai_next) {
      rc = sl__connect_once(a, deadline_ms, out);
      if (rc == SL_OK) {
        sl__tune(out->fd);
        freeaddrinfo(ai);
        return SL_OK;
      }
    }
    if (rc != SL_EREFUSED) break;
    if (sl__stopping()) {
      rc = SL_EINTERRUPTED;
      break;
    }
    int left = sl__remaining(deadline_ms);
    if (left <= 0) break;
    sl__sleep_ms(left < SL__CONNECT_RETRY_MS ? left : SL__CONNECT_RETRY_MS);
  }
  freeaddrinfo(ai);
  return rc;
}

int sl_send_all(sl_socket *s, const void *buf, size_t len, int64_t deadline_ms) {
  if (!s || s->fd < 0 || (!buf && len)) return SL_EINVAL;
  const uint8_t *p = (const uint8_t *)buf;
  while (len > 0) {
    const long n = (long)send(s->fd, (const char *)p, (int)(len > 1u << 30 ? 1u << 30 : len), SL__MSG_SEND);
    const int e = n < 0 ? sl__errno() : 0;
    if (n > 0) {
      p += n;
      len -= (size_t)n;
      continue;
    }
    if (n < 0 && e == SL__EINTR) continue;
    if (n < 0 && e == SL__EAGAIN) {
      int w = sl__wait(s, POLLOUT, deadline_ms);
      if (w < 0) return w;
      if (w == 0) return SL_ETIMEDOUT;
      continue;
    }
    if (n < 0 && (e == SL__EPIPE || e == SL__ECONNRESET)) return SL_ECLOSED;
    return sl__sys(s, e);
  }
  return SL_OK;
}

int sl_recv_all(sl_socket *s, void *buf, size_t len, int64_t deadline_ms) {
  if (!s || s->fd < 0 || (!buf && len)) return SL_EINVAL;
  uint8_t *p = (uint8_t *)buf;
  size_t got = 0;
  while (got < len) {
    const size_t want = len - got > 1u << 30 ? 1u << 30 : len - got;
    const long n = (long)recv(s->fd, (char *)(p + got), (int)want, SL__MSG_RECV);
    const int e = n < 0 ? sl__errno() : 0;
    if (n > 0) {
      got += (size_t)n;
      continue;
    }
    if (n == 0) return got == 0 ? SL_ECLOSED : SL_ETRUNCATED;
    if (e == SL__EINTR) continue;
    if (e == SL__EAGAIN) {
      int w = sl__wait(s, POLLIN, deadline_ms);
      if (w < 0) return w;
      if (w == 0) return SL_ETIMEDOUT;
      continue;
    }
    if (e == SL__ECONNRESET) return got == 0 ? SL_ECLOSED : SL_ETRUNCATED;
    return sl__sys(s, e);
  }
  return SL_OK;
}

void sl_close(sl_socket *s) {
  if (s && s->fd >= 0) {
    sl__close_fd(s->fd);
    s->fd = -1;
  }
}

int sl_wait_any(sl_socket *const *socks, size_t n, int64_t deadline_ms, int *ready) {
  if (!socks || !ready || n == 0 || n > 4096) return SL_EINVAL;
  struct pollfd p[4096];
  for (size_t i = 0; i < n; ++i) {
    p[i].fd = socks[i]->fd;
    p[i].events = POLLIN;
  }
  int r = sl__poll(p, (nfds_t)n, deadline_ms, socks[0]);
  if (r < 0) return r;
  int count = 0;
  for (size_t i = 0; i < n; ++i) {
    ready[i] = r > 0 && (p[i].revents & (POLLIN | POLLHUP | POLLERR)) != 0;
    count += ready[i];
  }
  return count;
}

int sl_peek(sl_socket *s, void *buf, size_t len) {
  if (!s || s->fd < 0 || (!buf && len)) return SL_EINVAL;
  for (;;) {
    const long r = (long)recv(s->fd, (char *)buf, (int)len, MSG_PEEK | SL__MSG_RECV);
    const int e = r < 0 ? sl__errno() : 0;
    if (r > 0) return (int)r;
    if (r == 0) return len == 0 ? 0 : SL_ECLOSED;
    if (e == SL__EINTR) continue;
    if (e == SL__EAGAIN) return 0;
    if (e == SL__ECONNRESET) return SL_ECLOSED;
    return sl__sys(s, e);
  }
}

void sl_peer_name(const sl_socket *s, char *out, size_t cap) {
  if (!out || cap == 0) return;
  snprintf(out, cap, "unknown peer");
  if (!s || s->fd < 0) return;
  struct sockaddr_storage a;
  socklen_t len = sizeof a;
  if (getpeername(s->fd, (struct sockaddr *)&a, &len) != 0) return;
  char host[INET6_ADDRSTRLEN] = "";
  int port = 0;
  if (a.ss_family == AF_INET) {
    const struct sockaddr_in *v4 = (const struct sockaddr_in *)&a;
    inet_ntop(AF_INET, &v4->sin_addr, host, sizeof host);
    port = ntohs(v4->sin_port);
    snprintf(out, cap, "%s:%d", host, port);
  } else if (a.ss_family == AF_INET6) {
    const struct sockaddr_in6 *v6 = (const struct sockaddr_in6 *)&a;
    inet_ntop(AF_INET6, &v6->sin6_addr, host, sizeof host);
    port = ntohs(v6->sin6_port);
    snprintf(out, cap, "[%s]:%d", host, port);
  }
}
