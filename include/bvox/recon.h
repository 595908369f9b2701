/* bvox/recon.h — (filled in by its issue). Included by bvox.h. */
#ifndef BVOX_RECON_H
#define BVOX_RECON_H

#endif /* BVOX_RECON_H */
