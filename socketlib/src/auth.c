/* Challenge-response proofs of the session token; see auth.h. */
#include "socketlib/auth.h"

#include <sodium.h>
#include <string.h>

#include "socketlib/socketlib.h"

int pcs_auth_init(void) { return sodium_init() >= 0 ? SL_OK : SL_ESYSTEM; }

void pcs_random_nonce(uint8_t out[PCS_NONCE_SIZE]) { randombytes_buf(out, PCS_NONCE_SIZE); }

void pcs_auth_proof(const char *token, size_t token_len, pcs_role role, const uint8_t client_nonce[PCS_NONCE_SIZE],
                    const uint8_t server_nonce[PCS_NONCE_SIZE], uint64_t table_hash,
                    uint8_t out[PCS_PROOF_SIZE]) {
  static const char *const labels[2] = {"pcs-v5 fe_server", "pcs-v5 host"};
  uint8_t hash_le[8];
  for (int i = 0; i < 8; ++i) hash_le[i] = (uint8_t)(table_hash >> (8 * i));
  static const char empty[1] = {0};
  const char *key = token ? token : empty;
  if (!token) token_len = 0;
  crypto_auth_hmacsha256_state st;
  crypto_auth_hmacsha256_init(&st, (const unsigned char *)key, token_len);
  const char *label = labels[role == PCS_ROLE_HOST ? 1 : 0];
  crypto_auth_hmacsha256_update(&st, (const unsigned char *)label, strlen(label) + 1); /* with its NUL */
  crypto_auth_hmacsha256_update(&st, client_nonce, PCS_NONCE_SIZE);
  crypto_auth_hmacsha256_update(&st, server_nonce, PCS_NONCE_SIZE);
  crypto_auth_hmacsha256_update(&st, hash_le, sizeof hash_le);
  crypto_auth_hmacsha256_final(&st, out);
  sodium_memzero(&st, sizeof st);
}

int pcs_auth_check(const char *token, size_t token_len, pcs_role role, const uint8_t client_nonce[PCS_NONCE_SIZE],
                   const uint8_t server_nonce[PCS_NONCE_SIZE], uint64_t table_hash,
                   const uint8_t proof[PCS_PROOF_SIZE]) {
  uint8_t expected[PCS_PROOF_SIZE];
  pcs_auth_proof(token, token_len, role, client_nonce, server_nonce, table_hash, expected);
  const int same = crypto_verify_32(expected, proof) == 0;
  sodium_memzero(expected, sizeof expected);
  return same;
}

void pcs_sha256(const uint8_t *data, size_t n, uint8_t out[PCS_SHA256_SIZE]) {
  crypto_hash_sha256(out, data, (unsigned long long)n);
}
