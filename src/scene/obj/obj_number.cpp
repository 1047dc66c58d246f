/*
 * obj_number.cpp: tinyobjloader 2.0.0rc10's number parser, operation for operation (obj_number.h).
 *
 * The control flow and every floating-point operation are those of rc10's tryParseDouble and
 * parseReal (tiny_obj_loader.h), in the same order and the same types, so the same doubles and
 * floats come out; only the reads at s_end (a blank or the line's end there, never a digit) are
 * guarded instead. Nothing may be "simplified" here: summing the integer digits in an integer or
 * the fraction as one division would round differently. The tests and the fuzz target compare
 * with the library on every input they see.
 */
#include "obj_number.h"

#include <cctype>
#include <cmath>
#include <cstdlib>
#include <string>

namespace obj_number {

namespace {

bool is_digit(char c) { return c >= '0' && c <= '9'; }

} // namespace

bool try_parse_double(const char *s, const char *s_end, double *result)
{
    if (s >= s_end)
        return false;
    double mantissa = 0.0;
    int exponent = 0; /* of ten; the result is ldexp(mantissa * 5^exponent, exponent) */
    char sign = '+', exp_sign = '+';
    const char *curr = s;
    int read = 0;
    bool end_not_reached = false, leading_decimal_dots = false;

    if (*curr == '+' || *curr == '-') {
        sign = *curr;
        curr++;
        if (curr != s_end && *curr == '.')
            leading_decimal_dots = true; /* "-.5" */
    } else if (is_digit(*curr)) {
    } else if (*curr == '.') {
        leading_decimal_dots = true; /* ".5" */
    } else {
        return false;
    }

    end_not_reached = curr != s_end;
    if (!leading_decimal_dots) {
        while (end_not_reached && is_digit(*curr)) {
            mantissa *= 10;
            mantissa += static_cast<int>(*curr - 0x30);
            curr++;
            read++;
            end_not_reached = curr != s_end;
        }
        if (read == 0)
            return false;
    }
    if (!end_not_reached)
        goto assemble;

    if (*curr == '.') {
        curr++;
        read = 1;
        end_not_reached = curr != s_end;
        while (end_not_reached && is_digit(*curr)) {
            static const double pow_lut[] = {
                1.0, 0.1, 0.01, 0.001, 0.0001, 0.00001, 0.000001, 0.0000001,
            };
            const int lut_entries = sizeof pow_lut / sizeof pow_lut[0];
            mantissa += static_cast<int>(*curr - 0x30) *
                        (read < lut_entries ? pow_lut[read] : std::pow(10.0, -read));
            read++;
            curr++;
            end_not_reached = curr != s_end;
        }
    } else if (*curr == 'e' || *curr == 'E') {
    } else {
        goto assemble;
    }
    if (!end_not_reached)
        goto assemble;

    if (*curr == 'e' || *curr == 'E') {
        curr++;
        end_not_reached = curr != s_end;
        if (end_not_reached && (*curr == '+' || *curr == '-')) {
            exp_sign = *curr;
            curr++;
        } else if (end_not_reached && is_digit(*curr)) {
        } else {
            return false; /* an empty exponent */
        }
        read = 0;
        end_not_reached = curr != s_end;
        while (end_not_reached && is_digit(*curr)) {
            if (exponent > 2147483647 / 10)
                return false; /* rc10's overflow check, one digit late (obj_scan.cpp refuses those) */
            exponent *= 10;
            exponent += static_cast<int>(*curr - 0x30);
            curr++;
            read++;
            end_not_reached = curr != s_end;
        }
        exponent *= (exp_sign == '+' ? 1 : -1);
        if (read == 0)
            return false;
    }

assemble:
    *result = (sign == '+' ? 1 : -1) *
              (exponent ? std::ldexp(mantissa * std::pow(5.0, exponent), exponent) : mantissa);
    return true;
}

float parse_real(const char *b, const char *e, double default_value)
{
    double value = default_value;
    try_parse_double(b, e, &value);
    return static_cast<float>(value);
}

bool is_short_decimal(const char *b, const char *e)
{
    const char *p = b;
    if (p < e && (*p == '+' || *p == '-'))
        p++;
    const char *int_start = p;
    while (p < e && is_digit(*p))
        p++;
    size_t int_digits = static_cast<size_t>(p - int_start), frac_digits = 0;
    if (p < e && *p == '.') {
        const char *frac_start = ++p;
        while (p < e && is_digit(*p))
            p++;
        frac_digits = static_cast<size_t>(p - frac_start);
    }
    return p == e && int_digits <= 9 && int_digits + frac_digits > 0;
}

bool is_plain_decimal(const char *b, const char *e)
{
    const char *p = b;
    if (p < e && (*p == '+' || *p == '-'))
        p++;
    size_t int_digits = 0, frac_digits = 0;
    while (p < e && is_digit(*p))
        p++, int_digits++;
    if (p < e && *p == '.') {
        p++;
        while (p < e && is_digit(*p))
            p++, frac_digits++;
    }
    if (int_digits + frac_digits == 0)
        return false;
    if (p < e && (*p == 'e' || *p == 'E')) {
        p++;
        if (p < e && (*p == '+' || *p == '-'))
            p++;
        size_t exp_digits = 0;
        while (p < e && is_digit(*p))
            p++, exp_digits++;
        if (exp_digits == 0)
            return false;
    }
    return p == e;
}

bool names_non_finite(const char *b, const char *e)
{
    std::string s(b, e);
    char *end = nullptr;
    double v = strtod(s.c_str(), &end);
    if (end && *end == '\0' && !std::isfinite(v))
        return true; /* nan, -nan, inf, infinity */
    for (char &c : s)
        c = static_cast<char>(toupper(static_cast<unsigned char>(c)));
    return s.find("#IND") != std::string::npos || s.find("#INF") != std::string::npos ||
           s.find("#QNAN") != std::string::npos; /* MSVC's printf of nan/inf */
}

bool exponent_too_long(const char *b, const char *e)
{
    const char *p = b;
    while (p < e && *p != 'e' && *p != 'E')
        p++;
    if (p < e)
        p++;
    if (p < e && (*p == '+' || *p == '-'))
        p++;
    while (p < e && *p == '0') /* leading zeros add nothing to the value */
        p++;
    size_t digits = 0;
    while (p < e && is_digit(*p))
        p++, digits++;
    return digits > 9;
}

} // namespace obj_number
