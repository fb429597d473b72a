/* hash.h - the one hash of rockfuzz: 64-bit FNV-1a, for result identities
 * (program and template files of an external model) and the FE state hashes
 * of the regression tests.  Not cryptographic.  Core layer. */
#ifndef ROCKFUZZ_CORE_HASH_H
#define ROCKFUZZ_CORE_HASH_H

#include <stddef.h>
#include <stdint.h>

/* The FNV-1a 64-bit offset basis: the h to start a hash with. */
#define RF_FNV1A_OFFSET 14695981039346656037ULL

/* FNV-1a over n bytes, continuing from h. */
uint64_t rf_fnv1a(uint64_t h, const void *data, size_t n);

#endif
