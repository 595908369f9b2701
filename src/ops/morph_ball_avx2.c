/* morph_ball_avx2.c — morph_ball_kern.h compiled with AVX2 (the build gives
 * *_avx2.c files those flags); chosen at run time by morph_ball.c. */
#define BALL_KERN(name) bvox__ball_##name##_avx2
#include "morph_ball_kern.h"
