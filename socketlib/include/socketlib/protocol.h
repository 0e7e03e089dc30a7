/*
 * The co-simulation wire protocol, all of it: magic, version, message types,
 * the fixed frame header and the payload codecs. Explicit little-endian,
 * length-prefixed frames; never raw structs on the wire.
 *
 * Frame = header (24 bytes) + payload (payload_size bytes):
 *   off size field
 *    0   4   magic         PCS_MAGIC ("PCSC" as bytes 50 43 53 43)
 *    4   2   version       PCS_PROTOCOL_VERSION of the sender
 *    6   2   type          pcs_msg_type
 *    8   8   step          coupling step index (0 for handshake messages)
 *   16   4   payload_size  bytes that follow, at most PCS_MAX_PAYLOAD
 *   20   4   reserved      0
 * The header layout never changes between versions, so a peer of another
 * version can still read an ABORT that says why it was refused.
 *
 * Handshake (auth.h): client sends HELLO with its nonce, server answers
 * CHALLENGE (its nonce), client sends AUTH (its proof of the token), server
 * checks it and answers HELLO_ACK with its own proof, which the client checks;
 * either side answers ABORT(reason) instead where a check fails. The token itself never
 * crosses the wire.
 * Each coupling step: client sends STEP k, server answers RESULT k; while a
 * step takes long the server sends HEARTBEAT k now and then, and the client
 * restarts its receive deadline on each, so a slow step is not a dead peer.
 * Either side may send ABORT(reason) at any time; BYE ends a session cleanly.
 *
 * Checkpoints (restart after a lost node or a wall-time limit): in place of
 * STEP k the client may send CHECKPOINT k; the server saves its state after
 * k completed steps and answers CHECKPOINT k with the file's path (a string
 * payload), then STEP k or BYE follows. A server restarted from such a file
 * expects RESUME k (the step its checkpoint holds) as the client's first
 * frame after HELLO_ACK and echoes it; a fresh server refuses RESUME and a
 * resumed one refuses STEP 0, each with an ABORT that says which side to
 * restart. A server that gets a stop signal sends STOPPING (before the next
 * RESULT) and keeps serving a grace period for the client's CHECKPOINT.
 */
#ifndef SOCKETLIB_PROTOCOL_H
#define SOCKETLIB_PROTOCOL_H

#include "socketlib/auth.h"
#include "socketlib/socketlib.h"

#ifdef __cplusplus
extern "C" {
#endif

#define PCS_MAGIC 0x43534350u /* bytes 'P','C','S','C' in little-endian order */
#define PCS_PROTOCOL_VERSION 6u /* 2: HEARTBEAT; 3: challenge-response (CHALLENGE, AUTH); 4: CHECKPOINT, RESUME;
                                   5: the client proves first, the server's proof moves to HELLO_ACK;
                                   6: HELLO_ACK names the session's FMU count, INPUTS */
#define PCS_HEADER_SIZE 24u
#define PCS_MAX_PAYLOAD (16u * 1024u * 1024u)
#define PCS_MAX_REASON 1024u

typedef enum {
  PCS_MSG_HELLO = 1,     /* client → server: version, port-table hash, dt, subcycles, client nonce */
  PCS_MSG_HELLO_ACK = 2, /* server → client: port-table hash, dt, subcycles, server's proof of the token */
  PCS_MSG_STEP = 3,      /* client → server: time, dt, input values */
  PCS_MSG_RESULT = 4,    /* server → client: time, output values */
  PCS_MSG_ABORT = 5,     /* either way: error code and reason text */
  PCS_MSG_BYE = 6,       /* client → server: session ends cleanly */
  PCS_MSG_HEARTBEAT = 7, /* server → client during a long step: "still computing step k" */
  PCS_MSG_CHALLENGE = 8, /* server → client: server nonce */
  PCS_MSG_AUTH = 9,      /* client → server: client's proof of the token */
  PCS_MSG_CHECKPOINT = 10, /* client → server: save state after step k; server → client: saved (path) */
  PCS_MSG_RESUME = 11,     /* client → server: continue from step k; server → client: agreed */
  PCS_MSG_STOPPING = 12,   /* server → client: got a stop signal, asks for CHECKPOINT soon */
  /* client → server, in a session of several FMUs: the inputs the importer
   * set for step k (time, dt, values, as STEP) before it stepped this FMU;
   * server → client: received (no payload). fe_server's coupling_server.hpp
   * (gather_round) says when the server takes them for final. */
  PCS_MSG_INPUTS = 13
} pcs_msg_type;

/* Name of a message type ("HELLO", ...), "UNKNOWN" otherwise. */
const char *pcs_msg_name(uint32_t type);

typedef struct {
  uint32_t magic;
  uint16_t version;
  uint16_t type;
  uint64_t step;
  uint32_t payload_size;
} pcs_header;

void pcs_encode_header(const pcs_header *h, uint8_t out[PCS_HEADER_SIZE]);
void pcs_decode_header(const uint8_t in[PCS_HEADER_SIZE], pcs_header *h);

/* Build header + payload in one buffer and send it with one write. */
int pcs_send_frame(sl_socket *s, uint16_t type, uint64_t step, const uint8_t *payload,
                   uint32_t payload_size, int64_t deadline_ms);

/* Receive one frame. The payload goes to buf (capacity cap). Checks, in order:
 * magic (SL_EBADMAGIC), length against PCS_MAX_PAYLOAD and cap (SL_EOVERSIZE).
 * A frame of another protocol version is returned whole with SL_EVERSION so
 * the caller can still read an ABORT from it or answer with one. */
int pcs_recv_frame(sl_socket *s, pcs_header *h, uint8_t *buf, uint32_t cap, int64_t deadline_ms);

/* ---- payload writer/reader: bounds-checked, little-endian ---- */
typedef struct {
  uint8_t *data;
  uint32_t cap;
  uint32_t len;
  int overflow; /* set when a put did not fit; the buffer is then unusable */
} pcs_writer;

void pcs_put_u16(pcs_writer *w, uint16_t v);
void pcs_put_u32(pcs_writer *w, uint32_t v);
void pcs_put_u64(pcs_writer *w, uint64_t v);
void pcs_put_f64(pcs_writer *w, double v);
void pcs_put_str(pcs_writer *w, const char *s); /* u32 length + bytes, no NUL */
void pcs_put_bytes(pcs_writer *w, const uint8_t *p, uint32_t n); /* n raw bytes, no length */

typedef struct {
  const uint8_t *data;
  uint32_t len;
  uint32_t pos;
  int error; /* set when a get ran past the end; values read after are 0 */
} pcs_reader;

uint16_t pcs_get_u16(pcs_reader *r);
uint32_t pcs_get_u32(pcs_reader *r);
uint64_t pcs_get_u64(pcs_reader *r);
double pcs_get_f64(pcs_reader *r);
/* Copies at most cap-1 bytes and NUL-terminates; longer strings set error. */
void pcs_get_str(pcs_reader *r, char *out, uint32_t cap);
/* n raw bytes into out (zeros and error set if fewer remain). */
void pcs_get_bytes(pcs_reader *r, uint8_t *out, uint32_t n);

/* ---- typed messages ---- */
typedef struct {
  uint16_t protocol_version;
  uint64_t table_hash; /* config::PortTable::hash() of the sender's port table */
  double dt;           /* coupling time step, s */
  uint32_t subcycles;  /* FE steps per coupling step */
  uint8_t client_nonce[PCS_NONCE_SIZE];
} pcs_hello;

typedef struct {
  uint8_t server_nonce[PCS_NONCE_SIZE];
} pcs_challenge;

typedef struct {
  uint8_t client_proof[PCS_PROOF_SIZE];
} pcs_auth;

typedef struct {
  uint64_t table_hash;
  double dt;
  uint32_t subcycles;
  uint8_t server_proof[PCS_PROOF_SIZE]; /* sent only after the client's proof was checked */
  uint32_t session_fmus; /* the FMUs (port tables) of the session: above 1, the client sends INPUTS */
} pcs_hello_ack;

typedef struct {
  uint32_t code; /* an sl_error or an application exit code */
  char reason[PCS_MAX_REASON];
} pcs_abort;

/* Encoders return the payload length, or SL_EOVERSIZE if cap is too small. */
int pcs_encode_hello(const pcs_hello *m, uint8_t *buf, uint32_t cap);
int pcs_decode_hello(const uint8_t *buf, uint32_t len, pcs_hello *m);
int pcs_encode_hello_ack(const pcs_hello_ack *m, uint8_t *buf, uint32_t cap);
int pcs_decode_hello_ack(const uint8_t *buf, uint32_t len, pcs_hello_ack *m);
int pcs_encode_challenge(const pcs_challenge *m, uint8_t *buf, uint32_t cap);
int pcs_decode_challenge(const uint8_t *buf, uint32_t len, pcs_challenge *m);
int pcs_encode_auth(const pcs_auth *m, uint8_t *buf, uint32_t cap);
int pcs_decode_auth(const uint8_t *buf, uint32_t len, pcs_auth *m);
int pcs_encode_abort(const pcs_abort *m, uint8_t *buf, uint32_t cap);
int pcs_decode_abort(const uint8_t *buf, uint32_t len, pcs_abort *m);

/* STEP and RESULT share one layout: time, dt, count, values[count]. */
int pcs_encode_values(double time, double dt, const double *values, uint32_t count, uint8_t *buf,
                      uint32_t cap);
/* Decodes into values (capacity max_count); *count receives the number sent.
 * SL_EMALFORMED if the count disagrees with the length or exceeds max_count. */
int pcs_decode_values(const uint8_t *buf, uint32_t len, double *time, double *dt, double *values,
                      uint32_t max_count, uint32_t *count);

/* Bytes needed for a values payload of count values. */
uint32_t pcs_values_size(uint32_t count);

/* A session of several FMUs: STEP and INPUTS carry the importer's thread
 * (process and thread id as one number) before the values' layout. */
int pcs_encode_tagged_values(uint64_t thread, double time, double dt, const double *values, uint32_t count,
                             uint8_t *buf, uint32_t cap);
int pcs_decode_tagged_values(const uint8_t *buf, uint32_t len, uint64_t *thread, double *time, double *dt,
                             double *values, uint32_t max_count, uint32_t *count);
uint32_t pcs_tagged_values_size(uint32_t count);

/* Send an ABORT with a formatted reason; ignores send errors (best effort,
 * the link may already be gone). */
void pcs_send_abort(sl_socket *s, uint64_t step, uint32_t code, const char *reason,
                    int64_t deadline_ms);

#ifdef __cplusplus
}
#endif
#endif
