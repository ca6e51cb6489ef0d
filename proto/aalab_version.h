/* The version of this build: project(VERSION) of CMakeLists.txt, the one place it is set, and
 * the git revision it was built from when there was one. Defined in a source generated at
 * configure time (aalab_version.c.in), so a new revision recompiles one file, not every file. */
#ifndef AALAB_VERSION_H
#define AALAB_VERSION_H

/* "0.1.0": what GET /v1/health reports. */
extern const char aalab_version[];
/* "0.1.0 (git 1e9a834053)", or "0.1.0" when not built from git: what --version prints. */
extern const char aalab_version_full[];

#endif
