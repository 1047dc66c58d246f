"""imagediff: reading and writing linear EXR images, and the error metrics that tools/compare
prints and tools/chart plots. Every metric takes (test, reference) as H x W x 3 float arrays of
linear radiance; docs/speed-vs-accuracy.md says what each one means."""
import numpy as np
import OpenEXR

# Relative errors divide by the reference plus this fraction of its mean, so that black pixels
# (an empty background, a deep shadow) do not divide by zero, and the measure stays the same when
# a scene's lights are all made ten times brighter.
RELATIVE_FLOOR = 0.01
# relMSE divides by reference^2 + 0.01 (Rousselle, Knaus and Zwicker 2011, and most denoising
# papers since): the usual convention, so its numbers compare with published ones.
RELMSE_EPSILON = 0.01


def read_exr(path):
    """The RGB channels of an EXR file as an H x W x 3 float32 array (R, G, B order)."""
    with OpenEXR.File(path) as f:
        channels = f.channels()
        if "RGB" in channels:
            rgb = channels["RGB"].pixels
        elif "RGBA" in channels:
            rgb = channels["RGBA"].pixels[..., :3]
        else:
            rgb = np.stack([channels[c].pixels for c in "RGB"], axis=-1)
    return np.ascontiguousarray(rgb, dtype=np.float32)


def write_exr(path, rgb):
    """Writes an H x W x 3 array as a float32 RGB EXR (ZIP compressed), as vkrt's EXRs are."""
    header = {"compression": OpenEXR.ZIP_COMPRESSION, "type": OpenEXR.scanlineimage}
    pixels = np.ascontiguousarray(rgb, dtype=np.float32)
    with OpenEXR.File(header, {"RGB": pixels}) as f:
        f.write(path)


def to_srgb(rgb, exposure=0.0):
    """Linear radiance to display values in [0, 1]: scaled by 2^exposure, clamped, sRGB-encoded
    (what vkrt writes to PNG)."""
    c = np.clip(rgb * 2.0 ** exposure, 0.0, 1.0)
    return np.where(c <= 0.0031308, 12.92 * c, 1.055 * np.power(c, 1 / 2.4) - 0.055)


def relative_error_map(test, ref):
    """Per-pixel |test - ref| / (ref + RELATIVE_FLOOR * mean(ref)), averaged over the channels."""
    floor = RELATIVE_FLOOR * max(float(ref.mean()), 1e-12)
    return (np.abs(test - ref) / (np.abs(ref) + floor)).mean(axis=-1)


def metrics(test, ref, perceptual=True):
    """A dict of error metrics of test against ref (same shape). 'perceptual' adds FLIP and
    SSIM, which take longer."""
    if test.shape != ref.shape:
        raise ValueError(f"images differ in size: {test.shape[1]}x{test.shape[0]} against "
                         f"{ref.shape[1]}x{ref.shape[0]}")
    test = test.astype(np.float64)
    ref = ref.astype(np.float64)
    diff = test - ref
    mse = float(np.mean(diff ** 2))
    out = {
        "rmse": mse ** 0.5,
        "relmse": float(np.mean(diff ** 2 / (ref ** 2 + RELMSE_EPSILON))),
        "mean_relative_error": float(relative_error_map(test, ref).mean()),
        "relative_bias": float(test.mean() / ref.mean() - 1.0) if ref.mean() > 0 else float("nan"),
    }
    display_mse = float(np.mean((to_srgb(test) - to_srgb(ref)) ** 2))
    out["psnr_db"] = 10.0 * np.log10(1.0 / display_mse) if display_mse > 0 else float("inf")
    if perceptual:
        import flip_evaluator
        from skimage.metrics import structural_similarity
        _, out["flip"], _ = flip_evaluator.evaluate(ref.astype(np.float32), test.astype(np.float32),
                                                   "HDR", applyMagma=False)
        out["flip"] = float(out["flip"])
        out["ssim"] = float(structural_similarity(to_srgb(ref), to_srgb(test), channel_axis=-1,
                                                  data_range=1.0))
    return out


def heatmap(test, ref, path, titles=("test", "reference"), scale=0.1):
    """Writes a PNG of three panels: test and reference as displayed, and the per-pixel relative
    error (relative_error_map) coloured from 0 to `scale` (brighter = larger; past it saturates)."""
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    err = relative_error_map(test.astype(np.float64), ref.astype(np.float64))
    aspect = ref.shape[1] / ref.shape[0]
    fig, axes = plt.subplots(1, 3, figsize=(3 * 2.6 * aspect + 0.8, 2.9), dpi=100,
                             gridspec_kw={"width_ratios": [1, 1, 1.12]})
    for ax, img, title in zip(axes[:2], (test, ref), titles):
        ax.imshow(to_srgb(img), interpolation="nearest")
        ax.set_title(title, fontsize=9)
    shown = axes[2].imshow(err, cmap="magma", vmin=0.0, vmax=scale, interpolation="nearest")
    axes[2].set_title(f"relative error (mean {err.mean():.2%})", fontsize=9)
    bar = fig.colorbar(shown, ax=axes[2], fraction=0.046, pad=0.03)
    bar.ax.yaxis.set_major_formatter(matplotlib.ticker.PercentFormatter(1.0, decimals=0))
    bar.ax.tick_params(labelsize=7)
    for ax in axes:
        ax.set_xticks([])
        ax.set_yticks([])
    fig.tight_layout()
    fig.savefig(path)
    plt.close(fig)
