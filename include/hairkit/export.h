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

#endif /* HAIRKIT_EXPORT_H */
