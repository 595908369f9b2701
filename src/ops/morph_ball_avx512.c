/* morph_ball_avx512.c — morph_ball_kern.h compiled with AVX512 (the build gives
 * *_avx512.c files those flags); chosen at run time by morph_ball.c. */
#define BALL_KERN(name) bvox__ball_##name##_avx512
#include "morph_ball_kern.h"
