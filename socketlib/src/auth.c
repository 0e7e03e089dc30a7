/* Challenge-response proofs of the session token; see auth.h.
 *
 * HMAC-SHA-256, SHA-256 and the nonces' randomness come from libsodium, or,
 * in the FMU's win64 DLL, from Windows' own CNG (bcrypt.dll), so the DLL
 * needs nothing beyond the system. Both give the same bytes (the handshake
 * between a win64 FMU and a Linux fe_server checks that in every session). */
#include "socketlib/auth.h"

#include <stdlib.h>
#include <string.h>

#include "socketlib/socketlib.h"

#ifdef _WIN32
#include <windows.h>
#include <bcrypt.h>
#else
#include <sodium.h>
#endif

/* One message of a digest: the proof hashes a few in turn. */
typedef struct {
  const void *data;
  size_t size;
} pcs__part;

#ifdef _WIN32
/* SHA-256 (key NULL) or HMAC-SHA-256 of the parts; 0 on a CNG failure, out zeroed. */
static int pcs__digest(const uint8_t *key, size_t key_len, const pcs__part *parts, size_t n, uint8_t out[32]) {
  /* HMAC pads its key with zeros to the block: an empty key is the key "\0". */
  static const uint8_t zero = 0;
  if (key && key_len == 0) key = &zero, key_len = 1;
  BCRYPT_ALG_HANDLE alg = NULL;
  BCRYPT_HASH_HANDLE h = NULL;
  int ok = 0;
  if (BCryptOpenAlgorithmProvider(&alg, BCRYPT_SHA256_ALGORITHM, NULL, key ? BCRYPT_ALG_HANDLE_HMAC_FLAG : 0) == 0) {
    if (BCryptCreateHash(alg, &h, NULL, 0, (PUCHAR)key, (ULONG)key_len, 0) == 0) {
      ok = 1;
      for (size_t i = 0; i < n && ok; ++i) ok = BCryptHashData(h, (PUCHAR)parts[i].data, (ULONG)parts[i].size, 0) == 0;
      ok = ok && BCryptFinishHash(h, out, 32, 0) == 0;
      BCryptDestroyHash(h);
    }
    BCryptCloseAlgorithmProvider(alg, 0);
  }
  if (!ok) memset(out, 0, 32); /* a proof of zeros: the peer refuses it, saying the proof does not match */
  return ok;
}
static void pcs__wipe(void *p, size_t n) { SecureZeroMemory(p, n); }
static int pcs__equal_32(const uint8_t *a, const uint8_t *b) {
  volatile uint8_t d = 0; /* every byte compared: the time says nothing of where they differ */
  for (int i = 0; i < 32; ++i) d |= (uint8_t)(a[i] ^ b[i]);
  return d == 0;
}
int pcs_auth_init(void) { return SL_OK; }
void pcs_random_nonce(uint8_t out[PCS_NONCE_SIZE]) {
  /* A nonce that is not random would let a recorded handshake be replayed: no fallback. */
  if (BCryptGenRandom(NULL, out, PCS_NONCE_SIZE, BCRYPT_USE_SYSTEM_PREFERRED_RNG) != 0) abort();
}
#else
static int pcs__digest(const uint8_t *key, size_t key_len, const pcs__part *parts, size_t n, uint8_t out[32]) {
  if (!key) {
    crypto_hash_sha256_state st;
    crypto_hash_sha256_init(&st);
    for (size_t i = 0; i < n; ++i) crypto_hash_sha256_update(&st, (const unsigned char *)parts[i].data, parts[i].size);
    crypto_hash_sha256_final(&st, out);
    return 1;
  }
  crypto_auth_hmacsha256_state st;
  crypto_auth_hmacsha256_init(&st, key, key_len);
  for (size_t i = 0; i < n; ++i) crypto_auth_hmacsha256_update(&st, (const unsigned char *)parts[i].data, parts[i].size);
  crypto_auth_hmacsha256_final(&st, out);
  sodium_memzero(&st, sizeof st);
  return 1;
}
static void pcs__wipe(void *p, size_t n) { sodium_memzero(p, n); }
static int pcs__equal_32(const uint8_t *a, const uint8_t *b) { return crypto_verify_32(a, b) == 0; }
int pcs_auth_init(void) { return sodium_init() >= 0 ? SL_OK : SL_ESYSTEM; }
void pcs_random_nonce(uint8_t out[PCS_NONCE_SIZE]) { randombytes_buf(out, PCS_NONCE_SIZE); }
#endif

void pcs_auth_proof(const char *token, size_t token_len, pcs_role role, const uint8_t client_nonce[PCS_NONCE_SIZE],
                    const uint8_t server_nonce[PCS_NONCE_SIZE], uint64_t table_hash,
                    uint8_t out[PCS_PROOF_SIZE]) {
  static const char *const labels[2] = {"pcs-v5 fe_server", "pcs-v5 host"};
  uint8_t hash_le[8];
  for (int i = 0; i < 8; ++i) hash_le[i] = (uint8_t)(table_hash >> (8 * i));
  static const uint8_t empty[1] = {0};
  const uint8_t *key = token ? (const uint8_t *)token : empty;
  if (!token) token_len = 0;
  const char *label = labels[role == PCS_ROLE_HOST ? 1 : 0];
  const pcs__part parts[4] = {{label, strlen(label) + 1}, /* with its NUL */
                              {client_nonce, PCS_NONCE_SIZE},
                              {server_nonce, PCS_NONCE_SIZE},
                              {hash_le, sizeof hash_le}};
  (void)pcs__digest(key, token_len, parts, 4, out);
}

int pcs_auth_check(const char *token, size_t token_len, pcs_role role, const uint8_t client_nonce[PCS_NONCE_SIZE],
                   const uint8_t server_nonce[PCS_NONCE_SIZE], uint64_t table_hash,
                   const uint8_t proof[PCS_PROOF_SIZE]) {
  uint8_t expected[PCS_PROOF_SIZE];
  pcs_auth_proof(token, token_len, role, client_nonce, server_nonce, table_hash, expected);
  const int same = pcs__equal_32(expected, proof);
  pcs__wipe(expected, sizeof expected);
  return same;
}

void pcs_sha256(const uint8_t *data, size_t n, uint8_t out[PCS_SHA256_SIZE]) {
  const pcs__part part = {data, n};
  (void)pcs__digest(NULL, 0, &part, 1, out);
}
