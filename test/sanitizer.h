/* ODECLOTH_ASAN: defined when the test is built with AddressSanitizer
 * (GCC says so with __SANITIZE_ADDRESS__, Clang with __has_feature). */
#ifndef ODECLOTH_TEST_SANITIZER_H
#define ODECLOTH_TEST_SANITIZER_H

#if defined(__SANITIZE_ADDRESS__)
#define ODECLOTH_ASAN 1
#elif defined(__has_feature)
#if __has_feature(address_sanitizer)
#define ODECLOTH_ASAN 1
#endif
#endif

#endif
