/*
 * Session authentication by challenge-response: the token never crosses the
 * wire, and each side proves to the other that it knows it.
 *
 *   client → server  HELLO      ... client nonce Nc (32 random bytes)
 *   server → client  CHALLENGE  server nonce Ns (nothing that depends on the token)
 *   client → server  AUTH       proof_client
 *   server → client  HELLO_ACK  ... proof_server (or ABORT with the reason)
 *
 *   proof_role = HMAC-SHA-256(key = token, "pcs-v5 " role || Nc || Ns || table hash)
 *
 * Order: the client proves first. A proof computed from the token is an
 * offline guess-checking oracle for whoever receives it (try a candidate
 * token, compare). A stranger that connects to the server knows the table
 * hash (the FMU's GUID is public) and chooses Nc, so a server that proved
 * first (protocol 4 did) handed every stranger such an oracle: a 3-character
 * token fell in 0.09 s. Now the server sends nothing token-derived to a peer
 * that has not proved it knows the token. What remains is the mirror case: a
 * host that connects to an impostor listening on the server's port gives the
 * impostor its proof. That needs the host to be pointed at the impostor, and
 * the 16-character minimum (config/token.hpp) puts a random token out of reach
 * of guessing (95^16 candidates). A password-authenticated key exchange
 * (CPace, SPAKE2) would close that case too; it is not needed for tokens made
 * by a random generator, which the messages tell users to make.
 *
 * The role label ("fe_server" or "host") makes the two proofs differ, so a
 * proof cannot be reflected back to the side that made it; fresh nonces from
 * both sides make every proof single-use. The key is exactly the token's
 * token_len bytes (a NUL inside cannot shorten it). HMAC and the random
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
typedef enum { PCS_ROLE_SERVER = 0, PCS_ROLE_HOST = 1 } pcs_role;

/* Initialise the crypto library (idempotent, thread-safe). SL_OK or SL_ESYSTEM. */
int pcs_auth_init(void);
/* Fill out with bytes from the operating system's random generator. */
void pcs_random_nonce(uint8_t out[PCS_NONCE_SIZE]);
/* The proof a side with `role` sends, keyed with the token_len bytes at token
 * (token_len 0: a server started with --insecure-no-token, loopback only). */
void pcs_auth_proof(const char *token, size_t token_len, pcs_role role, const uint8_t client_nonce[PCS_NONCE_SIZE],
                    const uint8_t server_nonce[PCS_NONCE_SIZE], uint64_t table_hash,
                    uint8_t out[PCS_PROOF_SIZE]);
/* 1 if `proof` is what a side with `role` and this token would send; compared
 * in constant time. */
int pcs_auth_check(const char *token, size_t token_len, pcs_role role, const uint8_t client_nonce[PCS_NONCE_SIZE],
                   const uint8_t server_nonce[PCS_NONCE_SIZE], uint64_t table_hash,
                   const uint8_t proof[PCS_PROOF_SIZE]);

/* SHA-256 of n bytes (libsodium): the checksum of checkpoint files. */
#define PCS_SHA256_SIZE 32u
void pcs_sha256(const uint8_t *data, size_t n, uint8_t out[PCS_SHA256_SIZE]);

#ifdef __cplusplus
}
#endif
#endif
