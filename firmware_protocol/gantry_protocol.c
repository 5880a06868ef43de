#include "gantry_protocol.h"

#include <string.h>

/* ---- field encoding, little-endian ---- */

static size_t put_u8(uint8_t* p, gp_u8 v) {
  p[0] = v;
  return 1;
}
static size_t put_u16(uint8_t* p, gp_u16 v) {
  p[0] = (uint8_t)(v & 0xFFu);
  p[1] = (uint8_t)(v >> 8);
  return 2;
}
static size_t put_u32(uint8_t* p, gp_u32 v) {
  p[0] = (uint8_t)(v & 0xFFu);
  p[1] = (uint8_t)((v >> 8) & 0xFFu);
  p[2] = (uint8_t)((v >> 16) & 0xFFu);
  p[3] = (uint8_t)(v >> 24);
  return 4;
}
static size_t put_i32(uint8_t* p, gp_i32 v) {
  return put_u32(p, (gp_u32)v);
}

static size_t get_u8(const uint8_t* p, gp_u8* v) {
  *v = p[0];
  return 1;
}
static size_t get_u16(const uint8_t* p, gp_u16* v) {
  *v = (gp_u16)(p[0] | (p[1] << 8));
  return 2;
}
static size_t get_u32(const uint8_t* p, gp_u32* v) {
  *v = (gp_u32)p[0] | ((gp_u32)p[1] << 8) | ((gp_u32)p[2] << 16) | ((gp_u32)p[3] << 24);
  return 4;
}
static size_t get_i32(const uint8_t* p, gp_i32* v) {
  gp_u32 u;
  size_t n = get_u32(p, &u);
  *v = (gp_i32)u; /* two's complement on every target we build for */
  return n;
}

enum { SIZE_u8 = 1, SIZE_u16 = 2, SIZE_u32 = 4, SIZE_i32 = 4 };

/* ---- generated from the table ---- */

int gp_payload_size(uint8_t id) {
  switch (id) {
#define FIELD(type, name) +SIZE_##type
#define MESSAGE(name, id, fields) \
  case id:                        \
    return 0 fields;
#include "gantry_messages.def"
#undef MESSAGE
#undef FIELD
    default:
      return -1;
  }
}

const char* gp_message_name(uint8_t id) {
  switch (id) {
#define FIELD(type, name)
#define MESSAGE(name, id, fields) \
  case id:                        \
    return #name;
#include "gantry_messages.def"
#undef MESSAGE
#undef FIELD
    default:
      return "?";
  }
}

static size_t encode_payload(const gp_message* m, uint8_t* p) {
  size_t n = 0;
  switch (m->id) {
#define FIELD(type, name) n += put_##type(p + n, body->name);
#define MESSAGE(name, id, fields)          \
  case id: {                               \
    const gp_##name* body = &m->body.name; \
    fields break;                          \
  }
#include "gantry_messages.def"
#undef MESSAGE
#undef FIELD
    default:
      break;
  }
  return n;
}

static void decode_payload(gp_message* m, const uint8_t* p) {
  size_t n = 0;
  switch (m->id) {
#define FIELD(type, name) n += get_##type(p + n, &body->name);
#define MESSAGE(name, id, fields)    \
  case id: {                         \
    gp_##name* body = &m->body.name; \
    fields break;                    \
  }
#include "gantry_messages.def"
#undef MESSAGE
#undef FIELD
    default:
      break;
  }
  (void)n;
}

const char* gp_axis_name(int axis) {
  switch (axis) {
#define AXIS(name, index) \
  case index:             \
    return #name;
#define FAULT(name, bit, meaning)
#include "gantry_vocabulary.def"
#undef FAULT
#undef AXIS
    default:
      return "?";
  }
}

const char* gp_fault_name(uint16_t bit) {
#define AXIS(name, index)
#define FAULT(name, b, meaning) \
  if (bit == (1u << b)) return #name;
#include "gantry_vocabulary.def"
#undef FAULT
#undef AXIS
  return "?";
}

const char* gp_fault_meaning(uint16_t bit) {
#define AXIS(name, index)
#define FAULT(name, b, meaning) \
  if (bit == (1u << b)) return meaning;
#include "gantry_vocabulary.def"
#undef FAULT
#undef AXIS
  return "an unknown fault bit";
}

/* The text the schema hash covers: the message table, then the vocabulary. */
#define STRINGIFY(x) #x
#define FIELD(type, name) type name;
#define MESSAGE(name, id, fields) #name "=" #id "{" STRINGIFY(fields) "}"
#define AXIS(name, index) "axis " #name "=" #index ";"
#define FAULT(name, bit, meaning) "fault " #name "=" #bit ";"
static const char kSchema[] =
#include "gantry_messages.def"
#include "gantry_vocabulary.def"
    ;
#undef FAULT
#undef AXIS
#undef MESSAGE
#undef FIELD

uint32_t gp_schema_hash(void) {
  uint32_t h = 2166136261u;
  size_t i;
  for (i = 0; kSchema[i] != '\0'; ++i) {
    h ^= (uint8_t)kSchema[i];
    h *= 16777619u;
  }
  return h;
}

uint16_t gp_crc16(const uint8_t* data, size_t length) {
  uint16_t crc = 0xFFFFu;
  size_t i;
  int bit;
  for (i = 0; i < length; ++i) {
    crc ^= (uint16_t)(data[i] << 8);
    for (bit = 0; bit < 8; ++bit)
      crc = (crc & 0x8000u) ? (uint16_t)((crc << 1) ^ 0x1021u) : (uint16_t)(crc << 1);
  }
  return crc;
}

size_t gp_encode(const gp_message* m, uint8_t* out, size_t capacity) {
  const int payload = gp_payload_size(m->id);
  size_t total;
  uint16_t crc;
  if (payload < 0) return 0;
  total = (size_t)payload + GP_FRAME_OVERHEAD;
  if (capacity < total) return 0;
  out[0] = GP_SYNC;
  out[1] = (uint8_t)payload;
  out[2] = m->sequence;
  out[3] = m->id;
  encode_payload(m, out + 4);
  crc = gp_crc16(out + 1, 3 + (size_t)payload);
  put_u16(out + 4 + payload, crc);
  return total;
}

/* ---- fields by name, for tests, logs and tools ---- */

int gp_set_field(gp_message* m, const char* field, int64_t value) {
  switch (m->id) {
#define FIELD(type, name)          \
  if (strcmp(field, #name) == 0) { \
    body->name = (gp_##type)value; \
    return 1;                      \
  }
#define MESSAGE(name, id, fields)    \
  case id: {                         \
    gp_##name* body = &m->body.name; \
    fields break;                    \
  }
#include "gantry_messages.def"
#undef MESSAGE
#undef FIELD
    default:
      break;
  }
  return 0;
}

int gp_get_field(const gp_message* m, const char* field, int64_t* value) {
  switch (m->id) {
#define FIELD(type, name)          \
  if (strcmp(field, #name) == 0) { \
    *value = (int64_t)body->name;  \
    return 1;                      \
  }
#define MESSAGE(name, id, fields)          \
  case id: {                               \
    const gp_##name* body = &m->body.name; \
    fields break;                          \
  }
#include "gantry_messages.def"
#undef MESSAGE
#undef FIELD
    default:
      break;
  }
  return 0;
}

/* ---- streaming decoder ---- */

void gp_decoder_init(gp_decoder* d) {
  memset(d, 0, sizeof *d);
}

static void drop(gp_decoder* d, size_t n) {
  memmove(d->buffer, d->buffer + n, d->length - n);
  d->length -= n;
}

int gp_decoder_next(gp_decoder* d, gp_message* out) {
  for (;;) {
    size_t skip = 0, length, total;
    int expected;
    uint16_t crc;
    while (skip < d->length && d->buffer[skip] != GP_SYNC) ++skip;
    if (skip) {
      d->dropped_bytes += skip;
      drop(d, skip);
    }
    if (d->length < 4) return 0;
    length = d->buffer[1];
    expected = gp_payload_size(d->buffer[3]);
    if (length > GP_MAX_PAYLOAD || expected < 0 || (size_t)expected != length) {
      /* Not a frame we could accept: resync from the next byte. */
      ++d->bad_frames;
      ++d->dropped_bytes;
      drop(d, 1);
      continue;
    }
    total = length + GP_FRAME_OVERHEAD;
    if (d->length < total) return 0;
    get_u16(d->buffer + 4 + length, &crc);
    if (crc != gp_crc16(d->buffer + 1, 3 + length)) {
      ++d->bad_frames;
      ++d->dropped_bytes;
      drop(d, 1);
      continue;
    }
    memset(out, 0, sizeof *out);
    out->sequence = d->buffer[2];
    out->id = d->buffer[3];
    decode_payload(out, d->buffer + 4);
    drop(d, total);
    return 1;
  }
}

int gp_decoder_push(gp_decoder* d, uint8_t byte, gp_message* out) {
  if (d->length == sizeof d->buffer) {
    /* Cannot happen with whole frames (a candidate is resolved by GP_MAX_FRAME bytes), but
     * never overrun: give up the oldest byte. */
    ++d->dropped_bytes;
    drop(d, 1);
  }
  d->buffer[d->length++] = byte;
  return gp_decoder_next(d, out);
}
