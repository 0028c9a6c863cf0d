// Storage type of the nn shaders: float, or float16_t (fp16 storage, fp32 arithmetic) when the
// including .comp defines NN_FP16 and enables GL_EXT_shader_16bit_storage.
#ifndef PENSIGHT_NN_TYPES_GLSL
#define PENSIGHT_NN_TYPES_GLSL
#ifdef NN_FP16
#define STORE float16_t
#define LD(v) float(v)
#define ST(v) float16_t(v)
#else
#define STORE float
#define LD(v) (v)
#define ST(v) (v)
#endif
#endif
