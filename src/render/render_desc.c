/* render_desc.c: a render description completed from the scene's settings (render_desc.h). */
#include "render_desc.h"

vkrt_render_desc vkrt_render_desc_complete(const vkrt_render_desc *asked, const vkrt_config *cfg)
{
    vkrt_render_desc d = *asked;
    d.width = d.width ? d.width : cfg->width;
    d.height = d.height ? d.height : cfg->height;
    d.samples = d.samples ? d.samples : cfg->samples;
    d.integrator = d.integrator ? d.integrator : cfg->integrator;
    d.max_depth = d.max_depth ? d.max_depth : cfg->max_depth;
    return d;
}
