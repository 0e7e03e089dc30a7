/* Frame and payload codecs of the wire protocol; see protocol.h. */
#include "socketlib/protocol.h"

#include <stdio.h>
#include <stdlib.h>
#include <string.h>

const char *pcs_msg_name(uint32_t type) {
  switch (type) {
    case PCS_MSG_HELLO: return "HELLO";
    case PCS_MSG_HELLO_ACK: return "HELLO_ACK";
    case PCS_MSG_STEP: return "STEP";
    case PCS_MSG_RESULT: return "RESULT";
    case PCS_MSG_ABORT: return "ABORT";
    case PCS_MSG_BYE: return "BYE";
    case PCS_MSG_HEARTBEAT: return "HEARTBEAT";
    case PCS_MSG_CHALLENGE: return "CHALLENGE";
    case PCS_MSG_AUTH: return "AUTH";
    case PCS_MSG_CHECKPOINT: return "CHECKPOINT";
    case PCS_MSG_RESUME: return "RESUME";
    case PCS_MSG_STOPPING: return "STOPPING";
    case PCS_MSG_INPUTS: return "INPUTS";
    default: return "UNKNOWN";
  }
}

static void pcs__le16(uint8_t *p, uint16_t v) {
  p[0] = (uint8_t)v;
  p[1] = (uint8_t)(v >> 8);
}
static void pcs__le32(uint8_t *p, uint32_t v) {
  for (int i = 0; i < 4; ++i) p[i] = (uint8_t)(v >> (8 * i));
}
static void pcs__le64(uint8_t *p, uint64_t v) {
  for (int i = 0; i < 8; ++i) p[i] = (uint8_t)(v >> (8 * i));
}
static uint16_t pcs__rd16(const uint8_t *p) { return (uint16_t)(p[0] | (p[1] << 8)); }
static uint32_t pcs__rd32(const uint8_t *p) {
  uint32_t v = 0;
  for (int i = 3; i >= 0; --i) v = (v << 8) | p[i];
  return v;
}
static uint64_t pcs__rd64(const uint8_t *p) {
  uint64_t v = 0;
  for (int i = 7; i >= 0; --i) v = (v << 8) | p[i];
  return v;
}

void pcs_encode_header(const pcs_header *h, uint8_t out[PCS_HEADER_SIZE]) {
  pcs__le32(out, h->magic);
  pcs__le16(out + 4, h->version);
  pcs__le16(out + 6, h->type);
  pcs__le64(out + 8, h->step);
  pcs__le32(out + 16, h->payload_size);
  pcs__le32(out + 20, 0);
}

void pcs_decode_header(const uint8_t in[PCS_HEADER_SIZE], pcs_header *h) {
  h->magic = pcs__rd32(in);
  h->version = pcs__rd16(in + 4);
  h->type = pcs__rd16(in + 6);
  h->step = pcs__rd64(in + 8);
  h->payload_size = pcs__rd32(in + 16);
}

int pcs_send_frame(sl_socket *s, uint16_t type, uint64_t step, const uint8_t *payload,
                   uint32_t payload_size, int64_t deadline_ms) {
  if (payload_size > PCS_MAX_PAYLOAD) return SL_EOVERSIZE;
  /* Header and payload in one buffer: one write per frame, so TCP_NODELAY
   * sends one segment instead of a header packet and a payload packet. */
  uint8_t small[PCS_HEADER_SIZE + 512];
  uint8_t *frame = small;
  size_t total = PCS_HEADER_SIZE + (size_t)payload_size;
  if (total > sizeof small) {
    frame = (uint8_t *)malloc(total);
    if (!frame) return SL_ENOMEM;
  }
  pcs_header h = {PCS_MAGIC, (uint16_t)PCS_PROTOCOL_VERSION, type, step, payload_size};
  pcs_encode_header(&h, frame);
  if (payload_size) memcpy(frame + PCS_HEADER_SIZE, payload, payload_size);
  int rc = sl_send_all(s, frame, total, deadline_ms);
  if (frame != small) free(frame);
  return rc;
}

int pcs_recv_frame(sl_socket *s, pcs_header *h, uint8_t *buf, uint32_t cap, int64_t deadline_ms) {
  uint8_t raw[PCS_HEADER_SIZE];
  int rc = sl_recv_all(s, raw, sizeof raw, deadline_ms);
  if (rc != SL_OK) return rc;
  pcs_decode_header(raw, h);
  if (h->magic != PCS_MAGIC) return SL_EBADMAGIC;
  if (h->payload_size > PCS_MAX_PAYLOAD || h->payload_size > cap) return SL_EOVERSIZE;
  if (h->payload_size) {
    rc = sl_recv_all(s, buf, h->payload_size, deadline_ms);
    if (rc == SL_ECLOSED) rc = SL_ETRUNCATED; /* the header came, the payload did not */
    if (rc != SL_OK) return rc;
  }
  return h->version == PCS_PROTOCOL_VERSION ? SL_OK : SL_EVERSION;
}

/* ---- writer / reader ---- */
static uint8_t *pcs__reserve(pcs_writer *w, uint32_t n) {
  if (w->overflow || w->cap - w->len < n) {
    w->overflow = 1;
    return NULL;
  }
  uint8_t *p = w->data + w->len;
  w->len += n;
  return p;
}
void pcs_put_u16(pcs_writer *w, uint16_t v) {
  uint8_t *p = pcs__reserve(w, 2);
  if (p) pcs__le16(p, v);
}
void pcs_put_u32(pcs_writer *w, uint32_t v) {
  uint8_t *p = pcs__reserve(w, 4);
  if (p) pcs__le32(p, v);
}
void pcs_put_u64(pcs_writer *w, uint64_t v) {
  uint8_t *p = pcs__reserve(w, 8);
  if (p) pcs__le64(p, v);
}
void pcs_put_f64(pcs_writer *w, double v) {
  uint64_t bits;
  memcpy(&bits, &v, sizeof bits); /* IEEE 754 binary64, sent little-endian */
  pcs_put_u64(w, bits);
}
void pcs_put_str(pcs_writer *w, const char *s) {
  size_t n = s ? strlen(s) : 0;
  if (n > PCS_MAX_PAYLOAD) {
    w->overflow = 1;
    return;
  }
  pcs_put_u32(w, (uint32_t)n);
  uint8_t *p = pcs__reserve(w, (uint32_t)n);
  if (p && n) memcpy(p, s, n);
}
void pcs_put_bytes(pcs_writer *w, const uint8_t *p, uint32_t n) {
  uint8_t *dst = pcs__reserve(w, n);
  if (dst && n) memcpy(dst, p, n);
}

static const uint8_t *pcs__take(pcs_reader *r, uint32_t n) {
  if (r->error || r->len - r->pos < n) {
    r->error = 1;
    return NULL;
  }
  const uint8_t *p = r->data + r->pos;
  r->pos += n;
  return p;
}
uint16_t pcs_get_u16(pcs_reader *r) {
  const uint8_t *p = pcs__take(r, 2);
  return p ? pcs__rd16(p) : 0;
}
uint32_t pcs_get_u32(pcs_reader *r) {
  const uint8_t *p = pcs__take(r, 4);
  return p ? pcs__rd32(p) : 0;
}
uint64_t pcs_get_u64(pcs_reader *r) {
  const uint8_t *p = pcs__take(r, 8);
  return p ? pcs__rd64(p) : 0;
}
double pcs_get_f64(pcs_reader *r) {
  uint64_t bits = pcs_get_u64(r);
  double v;
  memcpy(&v, &bits, sizeof v);
  return v;
}
void pcs_get_str(pcs_reader *r, char *out, uint32_t cap) {
  uint32_t n = pcs_get_u32(r);
  if (cap == 0) {
    r->error = 1;
    return;
  }
  out[0] = '\0';
  if (r->error) return;
  if (n >= cap) {
    r->error = 1;
    return;
  }
  const uint8_t *p = pcs__take(r, n);
  if (!p) return;
  memcpy(out, p, n);
  out[n] = '\0';
}
void pcs_get_bytes(pcs_reader *r, uint8_t *out, uint32_t n) {
  const uint8_t *p = pcs__take(r, n);
  if (p) memcpy(out, p, n);
  else memset(out, 0, n);
}

/* A payload must be consumed exactly: trailing bytes mean a layout mismatch. */
static int pcs__finish(const pcs_reader *r) {
  return (r->error || r->pos != r->len) ? SL_EMALFORMED : SL_OK;
}
static int pcs__written(const pcs_writer *w) { return w->overflow ? SL_EOVERSIZE : (int)w->len; }

int pcs_encode_hello(const pcs_hello *m, uint8_t *buf, uint32_t cap) {
  pcs_writer w = {buf, cap, 0, 0};
  pcs_put_u16(&w, m->protocol_version);
  pcs_put_u64(&w, m->table_hash);
  pcs_put_f64(&w, m->dt);
  pcs_put_u32(&w, m->subcycles);
  pcs_put_bytes(&w, m->client_nonce, PCS_NONCE_SIZE);
  return pcs__written(&w);
}
int pcs_decode_hello(const uint8_t *buf, uint32_t len, pcs_hello *m) {
  pcs_reader r = {buf, len, 0, 0};
  m->protocol_version = pcs_get_u16(&r);
  m->table_hash = pcs_get_u64(&r);
  m->dt = pcs_get_f64(&r);
  m->subcycles = pcs_get_u32(&r);
  pcs_get_bytes(&r, m->client_nonce, PCS_NONCE_SIZE);
  return pcs__finish(&r);
}

int pcs_encode_hello_ack(const pcs_hello_ack *m, uint8_t *buf, uint32_t cap) {
  pcs_writer w = {buf, cap, 0, 0};
  pcs_put_u64(&w, m->table_hash);
  pcs_put_f64(&w, m->dt);
  pcs_put_u32(&w, m->subcycles);
  pcs_put_bytes(&w, m->server_proof, PCS_PROOF_SIZE);
  pcs_put_u32(&w, m->session_fmus);
  return pcs__written(&w);
}
int pcs_decode_hello_ack(const uint8_t *buf, uint32_t len, pcs_hello_ack *m) {
  pcs_reader r = {buf, len, 0, 0};
  m->table_hash = pcs_get_u64(&r);
  m->dt = pcs_get_f64(&r);
  m->subcycles = pcs_get_u32(&r);
  pcs_get_bytes(&r, m->server_proof, PCS_PROOF_SIZE);
  m->session_fmus = pcs_get_u32(&r);
  return pcs__finish(&r);
}

int pcs_encode_challenge(const pcs_challenge *m, uint8_t *buf, uint32_t cap) {
  pcs_writer w = {buf, cap, 0, 0};
  pcs_put_bytes(&w, m->server_nonce, PCS_NONCE_SIZE);
  return pcs__written(&w);
}
int pcs_decode_challenge(const uint8_t *buf, uint32_t len, pcs_challenge *m) {
  pcs_reader r = {buf, len, 0, 0};
  pcs_get_bytes(&r, m->server_nonce, PCS_NONCE_SIZE);
  return pcs__finish(&r);
}

int pcs_encode_auth(const pcs_auth *m, uint8_t *buf, uint32_t cap) {
  pcs_writer w = {buf, cap, 0, 0};
  pcs_put_bytes(&w, m->client_proof, PCS_PROOF_SIZE);
  return pcs__written(&w);
}
int pcs_decode_auth(const uint8_t *buf, uint32_t len, pcs_auth *m) {
  pcs_reader r = {buf, len, 0, 0};
  pcs_get_bytes(&r, m->client_proof, PCS_PROOF_SIZE);
  return pcs__finish(&r);
}

int pcs_encode_abort(const pcs_abort *m, uint8_t *buf, uint32_t cap) {
  pcs_writer w = {buf, cap, 0, 0};
  pcs_put_u32(&w, m->code);
  pcs_put_str(&w, m->reason);
  return pcs__written(&w);
}
int pcs_decode_abort(const uint8_t *buf, uint32_t len, pcs_abort *m) {
  pcs_reader r = {buf, len, 0, 0};
  m->code = pcs_get_u32(&r);
  pcs_get_str(&r, m->reason, sizeof m->reason);
  return pcs__finish(&r);
}

uint32_t pcs_values_size(uint32_t count) { return 8u + 8u + 4u + 8u * count; }

int pcs_encode_values(double time, double dt, const double *values, uint32_t count, uint8_t *buf,
                      uint32_t cap) {
  pcs_writer w = {buf, cap, 0, 0};
  pcs_put_f64(&w, time);
  pcs_put_f64(&w, dt);
  pcs_put_u32(&w, count);
  for (uint32_t i = 0; i < count; ++i) pcs_put_f64(&w, values[i]);
  return pcs__written(&w);
}

int pcs_decode_values(const uint8_t *buf, uint32_t len, double *time, double *dt, double *values,
                      uint32_t max_count, uint32_t *count) {
  pcs_reader r = {buf, len, 0, 0};
  *time = pcs_get_f64(&r);
  *dt = pcs_get_f64(&r);
  *count = pcs_get_u32(&r);
  if (r.error || *count > max_count || len != pcs_values_size(*count)) return SL_EMALFORMED;
  for (uint32_t i = 0; i < *count; ++i) values[i] = pcs_get_f64(&r);
  return pcs__finish(&r);
}

uint32_t pcs_tagged_values_size(uint32_t count) { return 8u + pcs_values_size(count); }

int pcs_encode_tagged_values(uint64_t thread, double time, double dt, const double *values, uint32_t count,
                             uint8_t *buf, uint32_t cap) {
  pcs_writer w = {buf, cap, 0, 0};
  pcs_put_u64(&w, thread);
  if (w.overflow) return SL_EOVERSIZE;
  const int n = pcs_encode_values(time, dt, values, count, buf + w.len, cap - w.len);
  return n < 0 ? n : n + (int)w.len;
}

int pcs_decode_tagged_values(const uint8_t *buf, uint32_t len, uint64_t *thread, double *time, double *dt,
                             double *values, uint32_t max_count, uint32_t *count) {
  pcs_reader r = {buf, len, 0, 0};
  *thread = pcs_get_u64(&r);
  *count = 0;
  if (r.error) return SL_EMALFORMED;
  return pcs_decode_values(buf + r.pos, len - r.pos, time, dt, values, max_count, count);
}

void pcs_send_abort(sl_socket *s, uint64_t step, uint32_t code, const char *reason,
                    int64_t deadline_ms) {
  pcs_abort m;
  m.code = code;
  snprintf(m.reason, sizeof m.reason, "%s", reason ? reason : "");
  uint8_t buf[PCS_MAX_REASON + 16];
  int n = pcs_encode_abort(&m, buf, sizeof buf);
  if (n >= 0) (void)pcs_send_frame(s, PCS_MSG_ABORT, step, buf, (uint32_t)n, deadline_ms);
}
