"""A Mitsuba 3 BSDF that evaluates an acq SVBRDF map's data-driven BRDF per texel.

Written by `acq export mitsuba` (docs/export.md). Each texel's BRDF is the basis expansion the
map stores: x = q(bin) . c + mu(bin) in the NJR15 log-mapped space, then
rho = ((rho_ref + eps) exp(x) - eps) / cosw, exactly as `acq render view` evaluates it
(docs/svbrdf-map.md "Evaluating a pixel's BRDF"), with the map's row lookup (nearest MERL bin or
trilinear in bin-index space). Vectorised with Dr.Jit gathers, for the llvm (and cuda) variants.

The texel comes from the hit point on the sample plane (scene units are millimetres, the sample
centred at the origin in z = 0), so the quad must be placed as the scene script places it.
Sampling: cosine-weighted hemisphere (the lobe is not importance-sampled: with a point light
this costs nothing; under an environment a glossy ink needs many more samples, docs/export.md).
"""

import json
import os

import drjit as dr
import mitsuba as mi
import numpy as np

# The MERL grid and the log mapping, as src/core/merl_grid.h and src/brdf/log_mapping.h state.
THETA_H, THETA_D, PHI_D = 90, 90, 180
BINS = THETA_H * THETA_D * PHI_D
EPS = 0.001
COS_WEIGHT_MIN = 0.01
EDGE_SLACK = 1e-9
HALF_PI = np.pi / 2


def read_basis(path, k, crc32):
    """valid, ref, mean (BINS each) and the first k columns of q (BINS x k), per docs/basis-format.md."""
    header = np.fromfile(path, np.uint8, 128)
    if header[:8].tobytes() != b"ACQBASIS":
        raise ValueError(f"{path}: not an acq basis file")
    stored = int(np.frombuffer(header[28:32].tobytes(), np.uint32)[0])
    file_crc = int(np.frombuffer(header[120:124].tobytes(), np.uint32)[0])
    if f"{file_crc:08x}" != crc32.lower():
        raise ValueError(f"{path}: checksum {file_crc:08x}, the map was made with {crc32}")
    if stored < k:
        raise ValueError(f"{path}: {stored} components, the map needs {k}")
    off = np.frombuffer(header[56:96].tobytes(), np.uint64)
    valid = np.memmap(path, np.uint8, "r", offset=int(off[0]), shape=(BINS,))
    ref = np.memmap(path, np.float32, "r", offset=int(off[1]), shape=(BINS,))
    mean = np.memmap(path, np.float32, "r", offset=int(off[2]), shape=(BINS,))
    q = np.memmap(path, np.float32, "r", offset=int(off[4]), shape=(BINS, stored))
    return (np.array(valid, np.float32), np.array(ref), np.array(mean),
            np.ascontiguousarray(q[:, :k]))


def index_of(v, n):
    return dr.clip(mi.Int32(dr.floor(v + EDGE_SLACK)), 0, n - 1)


class AcqSvbrdf(mi.BSDF):
    def __init__(self, props):
        mi.BSDF.__init__(self, props)
        description = props["description"]
        with open(description) as f:
            d = json.load(f)
        here = os.path.dirname(os.path.abspath(description))
        self.width, self.height, self.k = d["width"], d["height"], d["components"]
        self.pixel_mm = d["pixel_size_mm"]
        self.interpolated = d["lookup"] == "interpolated"
        coefficients = np.fromfile(os.path.join(here, d["coefficients"]), np.float32)
        if coefficients.size != self.width * self.height * 3 * self.k:
            raise ValueError(f"{d['coefficients']}: {coefficients.size} floats, expected "
                             f"{self.width} x {self.height} x 3 x {self.k}")
        valid, ref, mean, q = read_basis(d["basis"], self.k, d["basis_crc32"])
        self.coefficients = mi.Float(coefficients)
        self.valid, self.ref, self.mean = mi.Float(valid), mi.Float(ref), mi.Float(mean)
        self.q = mi.Float(q.ravel())
        self.m_flags = mi.BSDFFlags.GlossyReflection | mi.BSDFFlags.FrontSide
        self.m_components = [self.m_flags]

    def texel(self, si):
        x = index_of(si.p.x / self.pixel_mm + self.width / 2, self.width)
        y = index_of(self.height / 2 - si.p.y / self.pixel_mm, self.height)  # rows along -y
        return mi.UInt32(y * self.width + x)

    def row(self, bin_index, active):
        """The k basis entries, mean, ref and validity of a bin."""
        base = mi.UInt32(bin_index) * self.k
        q = [dr.gather(mi.Float, self.q, base + j, active) for j in range(self.k)]
        return (q, dr.gather(mi.Float, self.mean, bin_index, active),
                dr.gather(mi.Float, self.ref, bin_index, active),
                dr.gather(mi.Float, self.valid, bin_index, active))

    def angles(self, light, camera):
        """Isotropic Rusinkiewicz angles, as src/core/rusinkiewicz.cpp computes them."""
        half = dr.normalize(light + camera)
        sin_h = dr.sqrt(half.x * half.x + half.y * half.y)
        cos_h = half.z
        theta_h = dr.atan2(sin_h, cos_h)
        pole = sin_h < 1e-7
        cos_p = dr.select(pole, 1.0, half.x / sin_h)
        sin_p = dr.select(pole, 0.0, half.y / sin_h)
        x1 = cos_p * light.x + sin_p * light.y
        y1 = -sin_p * light.x + cos_p * light.y
        dx = cos_h * x1 - sin_h * light.z
        dz = sin_h * x1 + cos_h * light.z
        theta_d = dr.atan2(dr.sqrt(dx * dx + y1 * y1), dz)
        phi_d = dr.atan2(y1, dx)
        return theta_h, theta_d, phi_d

    def sample_basis(self, light, camera, active):
        theta_h, theta_d, phi_d = self.angles(light, camera)
        if not self.interpolated:
            ih = dr.select(theta_h <= 0, 0, index_of(dr.sqrt(theta_h / HALF_PI) * THETA_H, THETA_H))
            idd = dr.select(theta_d <= 0, 0, index_of(theta_d / HALF_PI * THETA_D, THETA_D))
            phi = dr.select(phi_d < -EDGE_SLACK * np.pi / PHI_D, phi_d + np.pi, phi_d)
            ip = index_of(dr.maximum(phi, 0.0) / np.pi * PHI_D, PHI_D)
            b = mi.UInt32(ip + PHI_D * idd + PHI_D * THETA_D * ih)
            q, mean, ref, valid = self.row(b, active)
            return q, mean, ref, active & (valid > 0)
        # Trilinear in bin-index coordinates (src/brdf/basis_rows.cpp): bin centres at integers,
        # clamped at the theta ends, periodic in phi_d; masked corners left out, renormalised.
        gh = dr.sqrt(dr.maximum(theta_h, 0.0) / HALF_PI) * THETA_H - 0.5
        gd = theta_d / HALF_PI * THETA_D - 0.5
        gp = dr.select(phi_d < 0, phi_d + np.pi, phi_d) / np.pi * PHI_D - 0.5
        h0, d0, p0 = mi.Int32(dr.floor(gh)), mi.Int32(dr.floor(gd)), mi.Int32(dr.floor(gp))
        fh, fd, fp = gh - mi.Float(h0), gd - mi.Float(d0), gp - mi.Float(p0)
        q = [mi.Float(0.0) for _ in range(self.k)]
        mean, ref, total = mi.Float(0.0), mi.Float(0.0), mi.Float(0.0)
        for corner in range(8):
            dh, dd, dp = corner & 1, (corner >> 1) & 1, (corner >> 2) & 1
            bh = dr.clip(h0 + dh, 0, THETA_H - 1)
            bd = dr.clip(d0 + dd, 0, THETA_D - 1)
            bp = ((p0 + dp) % PHI_D + PHI_D) % PHI_D
            w = ((fh if dh else 1 - fh) * (fd if dd else 1 - fd) * (fp if dp else 1 - fp))
            b = mi.UInt32(bp + PHI_D * bd + PHI_D * THETA_D * bh)
            cq, cmean, cref, cvalid = self.row(b, active)
            w = dr.select((w > 0) & (cvalid > 0), w, 0.0)
            for j in range(self.k):
                q[j] += w * cq[j]
            mean += w * cmean
            ref += w * cref
            total += w
        inv = dr.select(total > 0, 1.0 / total, 0.0)
        return [v * inv for v in q], mean * inv, ref * inv, active & (total > 0)

    def brdf(self, si, light, camera, active):
        q, mean, ref, active = self.sample_basis(light, camera, active)
        cosw = dr.clip(light.z * camera.z, COS_WEIGHT_MIN, 1.0)
        base = self.texel(si) * (3 * self.k)
        rgb = []
        for c in range(3):
            x = mi.Float(mean)
            for j in range(self.k):
                x += q[j] * dr.gather(mi.Float, self.coefficients, base + c * self.k + j, active)
            rgb.append(dr.maximum(((ref + EPS) * dr.exp(x) - EPS) / cosw, 0.0))
        return dr.select(active, mi.Color3f(rgb[0], rgb[1], rgb[2]), mi.Color3f(0.0))

    def eval(self, ctx, si, wo, active=True):
        # Our "in" is the light (Mitsuba's wo in emitter sampling), "out" the camera (si.wi).
        cos_light, cos_camera = mi.Frame3f.cos_theta(wo), mi.Frame3f.cos_theta(si.wi)
        active = active & (cos_light > 0) & (cos_camera > 0)
        value = self.brdf(si, wo, si.wi, active) * cos_light
        return dr.select(active, value, mi.Color3f(0.0))

    def pdf(self, ctx, si, wo, active=True):
        ok = active & (mi.Frame3f.cos_theta(wo) > 0) & (mi.Frame3f.cos_theta(si.wi) > 0)
        return dr.select(ok, mi.warp.square_to_cosine_hemisphere_pdf(wo), 0.0)

    def eval_pdf(self, ctx, si, wo, active=True):
        return self.eval(ctx, si, wo, active), self.pdf(ctx, si, wo, active)

    def sample(self, ctx, si, sample1, sample2, active=True):
        wo = mi.warp.square_to_cosine_hemisphere(sample2)
        bs = mi.BSDFSample3f()
        bs.wo = wo
        bs.pdf = mi.warp.square_to_cosine_hemisphere_pdf(wo)
        bs.eta = 1.0
        bs.sampled_type = mi.UInt32(+mi.BSDFFlags.GlossyReflection)
        bs.sampled_component = 0
        active = active & (mi.Frame3f.cos_theta(si.wi) > 0) & (bs.pdf > 0)
        value = self.eval(ctx, si, wo, active) / dr.maximum(bs.pdf, 1e-12)
        return bs, dr.select(active, value, mi.Color3f(0.0))

    def traverse(self, callback):
        pass

    def to_string(self):
        return f"AcqSvbrdf[{self.width} x {self.height}, k = {self.k}]"


def register():
    mi.register_bsdf("acq_svbrdf", lambda props: AcqSvbrdf(props))
