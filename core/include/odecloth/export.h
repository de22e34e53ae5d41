/* ODECLOTH_API marks the libraries' public functions: the shared libraries
 * are built with hidden visibility, so only these are exported. */
#ifndef ODECLOTH_EXPORT_H
#define ODECLOTH_EXPORT_H

#if defined(__GNUC__) || defined(__clang__)
#define ODECLOTH_API __attribute__((visibility("default")))
#else
#define ODECLOTH_API
#endif

#endif
