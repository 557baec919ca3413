"""An animated GIF of a run, rendered headless (PyBullet's TinyRenderer).

Frames are taken by the simulator at every waypoint of a motion (and
between waypoints at most `STRIDE` radians apart), at both ends of a
primitive and after every human move; each carries the places' names and
a caption: the step, who acts and what, and the running measured cost
against E_p.
"""

from __future__ import annotations

from pathlib import Path

from PIL import Image, ImageDraw, ImageFont

from symsynth.files import atomic_output
from symsynth.execution.world import SimWorld
from symsynth.execution.render import default_camera, label_places, snapshot

CAMERA_DISTANCE = 1.3  # metres: closer than the scene picture's, the robot at work fills the frame
STRIDE = 0.25  # radians between frames along a motion
FRAME_MS = 90  # milliseconds each frame is shown
HOLD_MS = 600  # ... the frames after a human move and the last one
COLOURS = 32  # in the GIF's one palette
SAMPLES = 4  # frames the palette is made from


class Recorder:
    def __init__(self, world: SimWorld, path: Path, *, width: int = 480, height: int = 360) -> None:
        self.world = world
        self.path = Path(path)
        self.camera = default_camera(world.scene, width, height, distance=CAMERA_DISTANCE)
        self.frames: list[Image.Image] = []
        self.durations: list[int] = []

    def frame(self, caption: str, hold: bool = False) -> None:
        image = snapshot(self.world, self.camera)
        label_places(image, self.world.scene, self.camera)
        draw = ImageDraw.Draw(image)
        font = ImageFont.load_default(size=max(11, image.height // 30))
        left, top, right, bottom = draw.textbbox((0, 0), caption, font=font)
        draw.rectangle((0, 0, image.width, bottom - top + 10), fill=(255, 255, 255))
        draw.text((6 - left, 5 - top), caption, fill=(0, 0, 0), font=font)
        self.frames.append(image)
        self.durations.append(HOLD_MS if hold else FRAME_MS)

    def save(self) -> int:
        """Write the GIF; returns the number of frames."""
        if not self.frames:
            return 0
        self.durations[-1] = max(self.durations[-1], 4 * HOLD_MS)
        palette = self._palette()
        indexed = [frame.quantize(palette=palette, dither=Image.Dither.NONE) for frame in self.frames]
        with atomic_output(self.path, "recording") as temporary:
            indexed[0].save(temporary, format="GIF", save_all=True, append_images=indexed[1:],
                            duration=self.durations, loop=0, optimize=False)
        return len(self.frames)

    def _palette(self) -> Image.Image:
        """One palette of `COLOURS` for every frame, made from `SAMPLES`
        frames spread over the run, applied without dithering: what did
        not change between two frames has the same colours in both, and
        the GIF stores only the changed rectangle (a third of the size of
        a palette per frame, dithered)."""
        width, height = self.frames[0].size
        picked = self.frames[::max(1, len(self.frames) // SAMPLES)][:SAMPLES]
        sheet = Image.new("RGB", (width, height * len(picked)))
        for k, frame in enumerate(picked):
            sheet.paste(frame.convert("RGB"), (0, height * k))
        return sheet.convert("P", palette=Image.Palette.ADAPTIVE, colors=COLOURS)
