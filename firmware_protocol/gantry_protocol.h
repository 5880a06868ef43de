/* Gantry wire protocol codec (PROTOCOL.md). C99, no allocation, no dependencies: compiled
 * unchanged into the host driver and the (simulated) firmware. Message layouts come from
 * gantry_messages.def only. */
#ifndef GANTRY_PROTOCOL_H
#define GANTRY_PROTOCOL_H

#include <stddef.h>
#include <stdint.h>

#ifdef __cplusplus
extern "C" {
#endif

#define GP_SYNC 0xA5u
#define GP_PROTOCOL_VERSION 1u
#define GP_MAX_PAYLOAD 240u
#define GP_FRAME_OVERHEAD 6u /* sync, length, sequence, id, CRC-16 */
#define GP_MAX_FRAME (GP_MAX_PAYLOAD + GP_FRAME_OVERHEAD)

typedef uint8_t gp_u8;
typedef uint16_t gp_u16;
typedef uint32_t gp_u32;
typedef int32_t gp_i32;

enum gp_message_id {
#define FIELD(type, name)
#define MESSAGE(name, id, fields) GP_##name = id,
#include "gantry_messages.def"
#undef MESSAGE
#undef FIELD
};

enum gp_result_code {
  GP_OK = 0,
  GP_BUSY = 1,
  GP_NOT_HOMED = 2,
  GP_OUT_OF_RANGE = 3,
  GP_COLLISION = 4,
  GP_FAULT = 5,
  GP_LEASE_EXPIRED = 6,
  GP_BAD_REQUEST = 7,
  GP_DUPLICATE = 8
};

#define FIELD(type, name) gp_##type name;
#define MESSAGE(name, id, fields) \
  typedef struct {                \
    fields                        \
  } gp_##name;
#include "gantry_messages.def"
#undef MESSAGE
#undef FIELD

typedef struct {
  uint8_t sequence;
  uint8_t id; /* enum gp_message_id */
  union {
#define FIELD(type, name)
#define MESSAGE(name, id, fields) gp_##name name;
#include "gantry_messages.def"
#undef MESSAGE
#undef FIELD
  } body;
} gp_message;

/* The axes in the protocol's order and the fault bits (gantry_vocabulary.def). */
enum gp_axis {
#define AXIS(name, index) GP_AXIS_##name = index,
#define FAULT(name, bit, meaning)
#include "gantry_vocabulary.def"
#undef FAULT
#undef AXIS
  GP_AXIS_COUNT
};
enum gp_fault_bit {
#define AXIS(name, index)
#define FAULT(name, bit, meaning) GP_FAULT_BIT_##name = 1u << bit,
#include "gantry_vocabulary.def"
#undef FAULT
#undef AXIS
  GP_FAULT_BIT_NONE = 0
};

/* Name of an axis ("LIGHT_THETA"), or "?". */
const char* gp_axis_name(int axis);
/* Name and meaning of one fault bit ("STALL", "an axis did not follow its command"), or "?"
 * and "an unknown fault bit". */
const char* gp_fault_name(uint16_t bit);
const char* gp_fault_meaning(uint16_t bit);

/* The protocol's angle unit (millidegrees) from and to radians. */
static inline int32_t gp_mdeg_from_rad(double rad) {
  const double mdeg = rad * (180000.0 / 3.14159265358979323846);
  return (int32_t)(mdeg < 0 ? mdeg - 0.5 : mdeg + 0.5);
}
static inline double gp_rad_from_mdeg(int32_t mdeg) {
  return mdeg * (3.14159265358979323846 / 180000.0);
}

/* CRC-16/CCITT-FALSE: poly 0x1021, init 0xFFFF, no reflection, no final xor. */
uint16_t gp_crc16(const uint8_t* data, size_t length);

/* FNV-1a over the text of the message table: both sides compare it in the handshake. */
uint32_t gp_schema_hash(void);

/* Payload bytes of a message id, or -1 for an unknown id. */
int gp_payload_size(uint8_t id);

/* Name of a message id ("MOVE"), or "?" for an unknown one. */
const char* gp_message_name(uint8_t id);

/* Encodes a frame into out (capacity bytes); returns its size, or 0 for an unknown id or too
 * small a buffer. */
size_t gp_encode(const gp_message* message, uint8_t* out, size_t capacity);

/* A field of a message by name; return 0 when the message has no such field. */
int gp_set_field(gp_message* message, const char* field, int64_t value);
int gp_get_field(const gp_message* message, const char* field, int64_t* value);

/* Streaming decoder: push bytes as they arrive; whole, valid frames come out as messages.
 * Garbage, bad CRCs and mismatched lengths are skipped byte by byte (resync) and counted. */
typedef struct {
  uint8_t buffer[2 * GP_MAX_FRAME];
  size_t length;
  unsigned long dropped_bytes; /* bytes skipped while resynchronising */
  unsigned long bad_frames;    /* candidate frames rejected (CRC, id or length) */
} gp_decoder;

void gp_decoder_init(gp_decoder* decoder);
/* Appends one byte; returns 1 and fills *out when a message is complete. */
int gp_decoder_push(gp_decoder* decoder, uint8_t byte, gp_message* out);
/* Extracts a further message from bytes already buffered (call until it returns 0). */
int gp_decoder_next(gp_decoder* decoder, gp_message* out);

#ifdef __cplusplus
}
#endif

#endif /* GANTRY_PROTOCOL_H */
