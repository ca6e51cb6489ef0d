/* Default paths of the installed files, so that an installed aalabd needs no path flags while a
 * program run from the build tree still uses the source tree's files. */
#ifndef AALAB_INSTALL_PATHS_H
#define AALAB_INSTALL_PATHS_H

/* The dashboard directory served on the TCP listener: web/ of the source tree when this program
 * runs from its build tree (uninstalled), else the installed share/aalab/web. */
const char *install_default_web_dir(void);

#endif
