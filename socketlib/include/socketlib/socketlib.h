/*
 * socketlib: TCP sockets with deadlines, and the framed wire protocol
 * (protocol.h). C, libc only (auth.h adds libsodium); no printing.
 *
 * Every blocking call takes an absolute deadline on the monotonic clock
 * (sl_now_ms() + budget). A call that cannot finish by then returns
 * SL_ETIMEDOUT; a peer that closed cleanly gives SL_ECLOSED, one that closed
 * in the middle of a frame SL_ETRUNCATED. Errors are negative codes from the
 * one table below; sl_strerror() gives the message. For SL_ESYSTEM the errno
 * of the failing call is kept in sl_socket.sys_errno. Reads and writes never
 * block in the kernel (MSG_DONTWAIT + poll), whatever the descriptor's mode.
 *
 * The one process-wide setting: sl_set_stop_flag(). Once the flag is non-zero
 * (a signal handler sets it), every wait returns SL_EINTERRUPTED within
 * 200 ms instead of waiting on to its deadline.
 */
#ifndef SOCKETLIB_SOCKETLIB_H
#define SOCKETLIB_SOCKETLIB_H

#include <signal.h>
#include <stddef.h>
#include <stdint.h>

#ifdef __cplusplus
extern "C" {
#endif

/* X(name, value, message): the one table that makes the enum, names and messages. */
#define SL_ERRNO_MAP(X)                                                              \
  X(TIMEDOUT, -1, "timed out: the deadline passed before the operation finished")    \
  X(CLOSED, -2, "peer closed the connection")                                        \
  X(TRUNCATED, -3, "peer closed the connection in the middle of a frame")            \
  X(REFUSED, -4, "connection refused until the deadline (is the server running?)")   \
  X(BADMAGIC, -5, "frame does not start with the protocol magic (not our protocol)") \
  X(VERSION, -6, "peer speaks another protocol version")                             \
  X(OVERSIZE, -7, "frame length field exceeds the limit or the receive buffer")      \
  X(MALFORMED, -8, "payload does not match its message type")                        \
  X(ADDRESS, -9, "address could not be parsed or resolved")                          \
  X(SYSTEM, -10, "system call failed (see sys_errno)")                               \
  X(INVAL, -11, "invalid argument")                                                  \
  X(NOMEM, -12, "out of memory")                                                     \
  X(UNEXPECTED, -13, "unexpected message type or step index")                        \
  X(REFUSED_BY_PEER, -14, "peer refused the session (ABORT received)")           \
  X(INTERRUPTED, -15, "interrupted: the program was asked to stop (signal)")          \
  X(BUSY, -16, "the server is busy with another session")                           \
  X(CROWDED, -17, "the server dropped this connection to make room for newer ones (a connection flood?)")

typedef enum {
  SL_OK = 0,
#define SL__ENUM(name, value, msg) SL_E##name = (value),
  SL_ERRNO_MAP(SL__ENUM)
#undef SL__ENUM
} sl_error;

/* Message for an error code; never NULL. */
const char *sl_strerror(int code);
/* Symbolic name, e.g. "SL_ETIMEDOUT"; never NULL. */
const char *sl_err_name(int code);

typedef struct sl_socket {
  int fd;        /* -1 when closed */
  int sys_errno; /* errno of the last failing system call, 0 if none */
} sl_socket;

#define SL_SOCKET_INIT {-1, 0}

/* The flag that makes waits return SL_EINTERRUPTED (NULL: waits run to their
 * deadline). Set by the thread that does the waits (fe_server suspends it
 * while it reads a frame that has begun to arrive, so a signal never cuts a
 * frame in two), never while another thread waits. */
void sl_set_stop_flag(const volatile sig_atomic_t *flag);
const volatile sig_atomic_t *sl_get_stop_flag(void);

/* Milliseconds on the monotonic clock; add a budget to make a deadline. */
int64_t sl_now_ms(void);

/* Parse "HOST:PORT" (HOST may be a name, an IPv4 address or [IPv6]).
 * host_out receives at most host_cap-1 characters. SL_EADDRESS on bad input. */
int sl_parse_endpoint(const char *endpoint, char *host_out, size_t host_cap, int *port_out);

/* Bind and listen on host:port (port 0 = ephemeral). Does not block. */
int sl_listen(const char *host, int port, sl_socket *out);
/* The local port a bound socket got (useful after port 0); <0 on error. */
int sl_local_port(const sl_socket *s);
/* Wait for one connection until the deadline. SL_ETIMEDOUT if none came. */
int sl_accept(sl_socket *listener, int64_t deadline_ms, sl_socket *out);
/* Connect, retrying while the peer refuses (it may not be up yet) until the
 * deadline: SL_EREFUSED if it never listened, SL_ETIMEDOUT if it never answered.
 * Sets TCP_NODELAY on success. */
int sl_connect(const char *host, int port, int64_t deadline_ms, sl_socket *out);

/* Send all len bytes (one write in the normal case). SL_ECLOSED if the peer is
 * gone, SL_ETIMEDOUT if the socket stayed full until the deadline. */
int sl_send_all(sl_socket *s, const void *buf, size_t len, int64_t deadline_ms);
/* Receive exactly len bytes. SL_ECLOSED if the peer closed before the first
 * byte, SL_ETRUNCATED if it closed after some but not all, SL_ETIMEDOUT. */
int sl_recv_all(sl_socket *s, void *buf, size_t len, int64_t deadline_ms);

/* Wait until at least one of n sockets is readable (for a listener: a
 * connection is waiting; for a connection: bytes or the peer's close) or the
 * deadline passes. ready[i] is set to 1 for each readable socket, else 0.
 * Returns how many are ready (≥ 1), 0 at the deadline, or an error code. */
int sl_wait_any(sl_socket *const *socks, size_t n, int64_t deadline_ms, int *ready);
/* Copy up to len bytes that have arrived, without consuming them; never
 * blocks. Returns the count (0: nothing yet), SL_ECLOSED if the peer closed
 * with nothing left to read, or an error code. */
int sl_peek(sl_socket *s, void *buf, size_t len);
/* The peer's "address:port" for log lines ("unknown peer" if not known). */
void sl_peer_name(const sl_socket *s, char *out, size_t cap);

void sl_close(sl_socket *s);

#ifdef __cplusplus
}
#endif
#endif
