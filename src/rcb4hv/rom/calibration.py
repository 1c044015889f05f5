"""What an image's start-up tables say about the robot: the analog calibration (the AD
references, spec 10.4, 11.2, and what they say about the sensors at rest) and the servos its
allocation table configures."""

from __future__ import annotations

from rcb4hv.protocol.memory import AD_CHANNELS, NO_BLOCK, read_alloc
from rcb4hv.rom import layout as L

__all__ = ["ad_references", "calibrated_ad_inputs", "image_servos"]


def image_servos(rom: bytes | bytearray) -> tuple[int, ...]:
    """The ICS numbers the image's allocation table gives a servo block (the start-up program
    copies it to RAM): the servos of the robot the project was made for."""
    return tuple(
        n
        for n in range(L.SERVO_BLOCK_COPY_COUNT)
        if read_alloc(rom, n, at=L.ALLOC_IMAGE) != NO_BLOCK
    )


def ad_references(rom: bytes | bytearray) -> tuple[int, ...]:
    """AD0-AD10's references in the image (the words the start-up program copies to 000Ch)."""
    return AD_CHANNELS.unpack_from(rom, L.AD_REFERENCE_IMAGE)


def calibrated_ad_inputs(rom: bytes | bytearray) -> dict[int, int]:
    """``{channel: counts}``: what each calibrated sensor channel (AD1-AD10) reads at rest.

    HeartToHeart4's analog calibration stores each channel's reading at rest as its reference
    (spec 10.4), so a calibrated channel (reference 1..1023) reads its reference while the
    robot is still and its measured register reads 0; a reference of 0 (never calibrated) or
    FFFF (erased ROM) says nothing about the sensor."""
    return {ch: v for ch, v in enumerate(ad_references(rom)) if ch and 0 < v <= 1023}
