"""What the figure scripts of analysis/ share."""


def save_figure(fig, out):
    """Writes <out>.png from `fig` and names the two files a script wrote (<out>.csv too)."""
    fig.tight_layout()
    fig.savefig(out + ".png", dpi=130)
    print(f"{out}.csv, {out}.png")
