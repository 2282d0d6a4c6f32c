/* HK_API marks the functions of hairkit's public API. The library is compiled with
 * hidden visibility (-fvisibility=hidden), so the shared library exports exactly the
 * functions declared with HK_API; everything else stays inside it. HK_BUILDING_SHARED
 * is defined only while libhairkit.so itself is compiled; programs that include these
 * headers, and the static library, see an empty HK_API. */
#ifndef HAIRKIT_EXPORT_H
#define HAIRKIT_EXPORT_H

#if defined(HK_BUILDING_SHARED) && (defined(__GNUC__) || defined(__clang__))
#define HK_API __attribute__((visibility("default")))
#else
#define HK_API
#endif

/* printf-style format checking of a function's arguments (format string argument fmt,
 * first variadic argument first), placed after the declarator so that the declaration
 * stays on one line (tests/install checks HK_API declarations line by line). */
#if defined(__GNUC__)
#define HK_PRINTF_LIKE(fmt, first) __attribute__((format(printf, fmt, first)))
#else
#define HK_PRINTF_LIKE(fmt, first)
#endif

#endif /* HAIRKIT_EXPORT_H */
