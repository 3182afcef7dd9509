"""The class's address as a QR code, an SVG drawn here by the `qrcode` package (no outside service, so it
works on a school network without the internet)."""

from __future__ import annotations

import io

import qrcode
import qrcode.image.svg


def qr_svg(text: str) -> bytes:
    """An SVG of `text`'s QR code: black squares on white, with the standard quiet zone."""
    image = qrcode.make(text, image_factory=qrcode.image.svg.SvgPathFillImage, border=4,
                        error_correction=qrcode.constants.ERROR_CORRECT_M)
    out = io.BytesIO()
    image.save(out)
    return out.getvalue()
