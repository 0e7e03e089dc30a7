/*
 * Session authentication by challenge-response: the token never crosses the
 * wire, and each side proves to the other that it knows it.
 *
 *   client → server  HELLO      ... client nonce Nc (32 random bytes)
 *   server → client  CHALLENGE  server nonce Ns, proof_server
 *   client → server  AUTH       proof_client
 *   server → client  HELLO_ACK  (or ABORT with the reason)
 *
 *   proof_role = HMAC-SHA-256(key = token, "pcs-v3 " role || Nc || Ns || table hash)
 *
 * The role label ("fe_server" or "host") makes the two proofs differ, so a
 * proof cannot be reflected back to the side that made it; fresh nonces from
 * both sides make every proof single-use. The client checks the server's proof
 * before it sends its own: a host that reached something other than the real
 * server (same token) stops there and reveals nothing. HMAC and the random
 * numbers come from libsodium (RFC 2104 HMAC over SHA-256, FIPS 180-4).
 */
#ifndef SOCKETLIB_AUTH_H
#define SOCKETLIB_AUTH_H

#include <stdint.h>
#include <stddef.h>

#ifdef __cplusplus
extern "C" {
#endif

#define PCS_NONCE_SIZE 32u
#define PCS_PROOF_SIZE 32u
/* Off loopback fe_server refuses shorter tokens: 16 characters of a random
 * hex or base64 string carry at least 64 bits. */
#define PCS_MIN_TOKEN_OFF_LOOPBACK 16u

typedef enum { PCS_ROLE_SERVER = 0, PCS_ROLE_HOST = 1 } pcs_role;

/* Initialise the crypto library (idempotent, thread-safe). SL_OK or SL_ESYSTEM. */
int pcs_auth_init(void);
/* Fill out with bytes from the operating system's random generator. */
void pcs_random_nonce(uint8_t out[PCS_NONCE_SIZE]);
/* The proof a side with `role` sends; token may be "" (loopback only). */
void pcs_auth_proof(const char *token, pcs_role role, const uint8_t client_nonce[PCS_NONCE_SIZE],
                    const uint8_t server_nonce[PCS_NONCE_SIZE], uint64_t table_hash,
                    uint8_t out[PCS_PROOF_SIZE]);
/* 1 if `proof` is what a side with `role` and this token would send; compared
 * in constant time. */
int pcs_auth_check(const char *token, pcs_role role, const uint8_t client_nonce[PCS_NONCE_SIZE],
                   const uint8_t server_nonce[PCS_NONCE_SIZE], uint64_t table_hash,
                   const uint8_t proof[PCS_PROOF_SIZE]);

/* SHA-256 of n bytes (libsodium): the checksum of checkpoint files. */
#define PCS_SHA256_SIZE 32u
void pcs_sha256(const uint8_t *data, size_t n, uint8_t out[PCS_SHA256_SIZE]);

#ifdef __cplusplus
}
#endif
#endif
