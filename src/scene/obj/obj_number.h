/*
 * obj_number.h: tinyobjloader's number parser, reproduced (internal to the OBJ loader).
 *
 * rc10 reads every v, vt and vn number with its own tryParseDouble, which is not strtod: it sums
 * the digits in doubles one at a time (a fraction digit times 10^-k from a table) and scales by
 * ldexp(m * pow(5, e), e), then rounds to float. Its double differs from strtod's correctly
 * rounded one for about a third of plain decimals, and its float for about one number with an
 * exponent in 2,000-4,000 ("27194.9930e3"; measured on random numbers; never seen for a plain
 * decimal, but not proved), so vkrt repeats those operations one for one: each float is the one
 * tinyobjloader's LoadObj gives (tests/test_obj_number.cpp holds it to the library's LoadObj,
 * fuzz/fuzz_obj_number.cpp to the function itself). The strict grammar the OBJ and .mtl checks
 * hold numbers to (is_plain_decimal and its neighbours) lives here too. C++ only.
 */
#ifndef VKRT_OBJ_NUMBER_H
#define VKRT_OBJ_NUMBER_H

namespace obj_number {

/* rc10's tryParseDouble on [s, s_end): true and *result set if it reads a number (greedily: "3.1+e2"
 * reads 3.1), false and *result untouched otherwise (an empty span, no digit, an empty exponent,
 * an exponent past INT_MAX / 10 before its last digit). s_end is never read. */
bool try_parse_double(const char *s, const char *s_end, double *result);

/* rc10's parseReal on one blank-free token [b, e): the float it reads, or default_value where
 * try_parse_double fails (a missing token is the empty span). */
float parse_real(const char *b, const char *e, double default_value);

/* Whether [b, e) is [sign] digits [. digits] or [sign] . digits, with at most 9 digits before the
 * point. Such a number is finite, fits a float and lies inside VKRT_COORDINATE_LIMIT however it is
 * rounded (under 1e9 + 1), and has no exponent: every check of the pre-scan passes, so it runs
 * none of them (obj_scan.cpp). */
bool is_short_decimal(const char *b, const char *e);

/* Whether [b, e) is a plain decimal as tinyobjloader understands it:
 * [sign] (digits[.digits*] | .digits) [e[sign]digits]. strtod alone would also take hex, "nan"
 * and "inf", which tinyobjloader reads as 0. */
bool is_plain_decimal(const char *b, const char *e);

/* Whether [b, e) names a value that is not finite: "nan", "inf", "infinity" (strtod's words, any
 * case and sign) or MSVC's printf of them ("1.#IND", "1.#INF", "1.#QNAN"). */
bool names_non_finite(const char *b, const char *e);

/* Whether [b, e) has an exponent of more than 9 significant digits. rc10's tryParseDouble
 * accumulates the exponent in an int, checking for overflow one digit too late, so such a
 * number ("1e-2147483649") is undefined behaviour there: the loader refuses it before
 * tinyobjloader runs. */
bool exponent_too_long(const char *b, const char *e);

} // namespace obj_number

#endif
