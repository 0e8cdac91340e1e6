"""glTF's dielectric-over-diffuse material as lvcl defines it
(kernels/closure/plastic.h), as a Mitsuba 3 BSDF plugin, "gltf_plastic".

Mitsuba's own plastic and roughplastic layer the coat differently (internal
reflections between coat and base, rough Fresnel averages): on the kitchen
their diffuse part came out 4.5% brighter than lvcl's. This plugin
evaluates the same formula lvcl does, so a reference measures lvcl's light
transport rather than the two layering models:

    f cos = (1 - F(cos_o)) (1 - F(cos_i)) base / pi cos_i
          + F(wo . h) D(h) G2(wo, wi) / (4 cos_o)

with F Schlick's Fresnel from f0 = ((ior - 1) / (ior + 1))^2 times the
KHR_materials_specular colour, D the GGX distribution of alpha, G2 the
height-correlated Smith term. Below alpha = 1e-3 the coat is a mirror of
weight F(cos_o). Sampling (the coat with probability from each layer's
reflectance, else the cosine hemisphere; the coat by GGX visible normals)
only has to be unbiased, and it is: pdf() is its density.

    register()   once a Mitsuba variant is set; then {"type": "gltf_plastic",
                 "base": texture, "specular": rgb, "f0": float, "alpha": float}
"""

SMOOTH_ALPHA = 1e-3  # LV_SMOOTH_ALPHA


def register():
    import drjit as dr
    import mitsuba as mi

    if "gltf_plastic" in getattr(register, "done", set()):
        return

    def luminance(c):
        return 0.2126 * c[0] + 0.7152 * c[1] + 0.0722 * c[2]

    class Constant:
        """An rgb property, read like a texture."""

        def __init__(self, value):
            self.value = mi.Color3f(value)

        def eval(self, si):
            return self.value

    def texture(value):
        return value if hasattr(value, "eval") else Constant(value)

    class GltfPlastic(mi.BSDF):
        def __init__(self, props):
            mi.BSDF.__init__(self, props)
            self.base = texture(props["base"])
            self.specular = texture(props["specular"])
            self.f0 = props.get("f0", 0.04)
            self.alpha = props.get("alpha", 0.0)
            self.smooth = self.alpha < SMOOTH_ALPHA
            coat = mi.BSDFFlags.DeltaReflection if self.smooth else mi.BSDFFlags.GlossyReflection
            front = mi.BSDFFlags.FrontSide
            self.m_components = [coat | front, mi.BSDFFlags.DiffuseReflection | front]
            self.m_flags = coat | mi.BSDFFlags.DiffuseReflection | front
            if not self.smooth:
                self.distr = mi.MicrofacetDistribution(mi.MicrofacetType.GGX, self.alpha, True)

        def fresnel(self, si, c):
            m = dr.clip(1.0 - c, 0.0, 1.0)
            return self.specular.eval(si) * (self.f0 + (1.0 - self.f0) * (m * m * m * m * m))

        def coat_probability(self, si, cos_o):
            fs = luminance(self.fresnel(si, cos_o))
            fd = (1.0 - fs) * luminance(self.base.eval(si))
            return dr.select(fs + fd > 0.0, dr.clip(fs / (fs + fd), 0.05, 0.95), 0.5)

        def lam(self, c):
            c2 = c * c
            t2 = dr.maximum(0.0, 1.0 - c2) / c2
            return 0.5 * (dr.sqrt(1.0 + self.alpha * self.alpha * t2) - 1.0)

        def value(self, si, wo):
            """f cos for si.wi (lvcl's wo) and wo (lvcl's wi)."""
            cos_o, cos_i = mi.Frame3f.cos_theta(si.wi), mi.Frame3f.cos_theta(wo)
            base = self.base.eval(si)
            v = (1.0 - self.fresnel(si, cos_o)) * (1.0 - self.fresnel(si, cos_i)) * base * (cos_i / dr.pi)
            if not self.smooth:
                h = dr.normalize(si.wi + wo)
                a2 = self.alpha * self.alpha
                k = h.z * h.z * (a2 - 1.0) + 1.0
                d = a2 / (dr.pi * k * k)
                g2 = 1.0 / (1.0 + self.lam(cos_o) + self.lam(cos_i))
                v += self.fresnel(si, dr.dot(si.wi, h)) * d * g2 / (4.0 * cos_o)
            return dr.select((cos_o > 0.0) & (cos_i > 0.0), v, 0.0)

        def density(self, si, wo):
            cos_o, cos_i = mi.Frame3f.cos_theta(si.wi), mi.Frame3f.cos_theta(wo)
            pc = self.coat_probability(si, cos_o)
            p = (1.0 - pc) * cos_i / dr.pi
            if not self.smooth:
                h = dr.normalize(si.wi + wo)
                p += pc * self.distr.pdf(si.wi, h) / (4.0 * dr.abs(dr.dot(si.wi, h)))
            return dr.select((cos_o > 0.0) & (cos_i > 0.0), p, 0.0)

        def sample(self, ctx, si, sample1, sample2, active):
            cos_o = mi.Frame3f.cos_theta(si.wi)
            active &= cos_o > 0.0
            pc = self.coat_probability(si, cos_o)
            coat = sample1 < pc
            bs = dr.zeros(mi.BSDFSample3f)
            if self.smooth:
                wo = dr.select(coat, mi.reflect(si.wi), mi.warp.square_to_cosine_hemisphere(sample2))
            else:
                h, _ = self.distr.sample(si.wi, sample2)
                wo = dr.select(coat, mi.reflect(si.wi, h), mi.warp.square_to_cosine_hemisphere(sample2))
            bs.wo = wo
            bs.eta = 1.0
            if self.smooth:
                bs.sampled_component = dr.select(coat, 0, 1)
                bs.sampled_type = dr.select(coat, mi.UInt32(+mi.BSDFFlags.DeltaReflection),
                                            mi.UInt32(+mi.BSDFFlags.DiffuseReflection))
                diffuse_pdf = (1.0 - pc) * mi.Frame3f.cos_theta(wo) / dr.pi
                bs.pdf = dr.select(coat, pc, diffuse_pdf)
                weight = dr.select(coat, self.fresnel(si, cos_o) / pc,
                                   self.value(si, wo) / dr.maximum(diffuse_pdf, 1e-20))
            else:
                bs.sampled_component = dr.select(coat, 0, 1)
                bs.sampled_type = dr.select(coat, mi.UInt32(+mi.BSDFFlags.GlossyReflection),
                                            mi.UInt32(+mi.BSDFFlags.DiffuseReflection))
                bs.pdf = self.density(si, wo)
                weight = self.value(si, wo) / dr.maximum(bs.pdf, 1e-20)
            active &= (bs.pdf > 0.0) & (mi.Frame3f.cos_theta(wo) > 0.0)
            return (bs, dr.select(active, mi.Color3f(weight), 0.0))

        def eval(self, ctx, si, wo, active):
            return dr.select(active, mi.Color3f(self.value(si, wo)), 0.0)

        def pdf(self, ctx, si, wo, active):
            return dr.select(active, self.density(si, wo), 0.0)

        def eval_pdf(self, ctx, si, wo, active):
            return (self.eval(ctx, si, wo, active), self.pdf(ctx, si, wo, active))

        def to_string(self):
            return "GltfPlastic[alpha=%g, f0=%g]" % (self.alpha, self.f0)

    mi.register_bsdf("gltf_plastic", lambda props: GltfPlastic(props))
    register.done = getattr(register, "done", set()) | {"gltf_plastic"}
