/*
 * fuzz_obj_number.cpp: libFuzzer target holding the OBJ loader's number parser
 * (src/scene/obj_number.h) to tinyobjloader's own tryParseDouble, on any bytes.
 *
 * This file compiles tinyobjloader's implementation (-DTINYOBJLOADER_IMPLEMENTATION, as every
 * fuzz target's C++ does), so its file-local tryParseDouble is callable here. Each input is one
 * span; both parsers must agree on whether it is a number and, if so, on the double's bits and
 * on the float parseReal makes of it. The span is followed by a NUL, as a token is by a blank or
 * the line's end: rc10 reads that byte. Inputs with an exponent of ten or more digits are skipped:
 * rc10 overflows an int on them (the pre-scan refuses them, obj_scan.h).
 */
#include <tiny_obj_loader.h>

#include <cstddef>
#include <cstdint>
#include <cstdlib>
#include <cstring>
#include <string>

#include "scene/obj/obj_number.h"

namespace {

/* A run of ten or more digits after an 'e' or 'E'. */
bool has_long_exponent(const std::string &s)
{
    size_t run = 0;
    bool after_e = false;
    for (char c : s) {
        if (c == 'e' || c == 'E')
            after_e = true, run = 0;
        else if (c >= '0' && c <= '9')
            run += after_e;
        else
            run = 0;
        if (run >= 10)
            return true;
    }
    return false;
}

} // namespace

extern "C" int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size)
{
    std::string s(reinterpret_cast<const char *>(data), size); /* NUL-terminated copy */
    if (has_long_exponent(s))
        return 0;
    const char *b = s.c_str(), *e = b + size;
    double want = 7.0, got = 7.0;
    bool want_ok = tinyobj::tryParseDouble(b, e, &want);
    bool got_ok = obj_number::try_parse_double(b, e, &got);
    if (want_ok != got_ok || memcmp(&want, &got, sizeof want) != 0)
        abort();
    float want_f = static_cast<float>(want_ok ? want : 0.0), got_f = obj_number::parse_real(b, e, 0.0);
    if (memcmp(&want_f, &got_f, sizeof want_f) != 0)
        abort();
    return 0;
}
