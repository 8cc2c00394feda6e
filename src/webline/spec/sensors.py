"""Sensors of a line file (``[[sensors]]``): the loadcells and speed encoders the controllers
read, with their calibration. A sensor acts where its controller reads the signal (inside the
loop): a loadcell reading 3 % high makes its tension loop hold the web 3 % below its set
point. Lines without ``[[sensors]]`` have ideal sensors (gain 1, offset 0, scale 1).
docs/line-file.md, "sensors"; docs/commissioning.md, "Sensors in the model"."""

from __future__ import annotations

from collections.abc import Callable
from typing import Annotated, Literal, NoReturn

from pydantic import Field

from webline.spec.disturbances import Name
from webline.spec.quantities import Strict, TimeNonNeg, si


class LoadcellSensor(Strict):
    """A loadcell on a zone's tension span: its controller reads ``gain`` T + ``offset``
    [N] where the web carries T [N], ``delay`` [s] late (rounded to whole controller
    samples). ``span``: the span whose tension reference marks it (the zone's loadcell
    span)."""

    name: Name
    type: Literal["loadcell"]
    span: Name
    gain: Annotated[float, si("dimensionless", ">0")] = 1.0
    offset: Annotated[float, si("force")] = 0.0
    delay: TimeNonNeg = 0.0


class EncoderSensor(Strict):
    """The speed encoder of a driven roller or roll: its drive's speed loop, the diameter
    calculator and a result's ``speed_measured`` read ``scale`` x the true surface speed
    (a wrong roller diameter or pulse count in the drive's parameters); the speed loop reads
    it ``delay`` [s] late (rounded to whole controller samples)."""

    name: Name
    type: Literal["encoder"]
    roller: Name
    scale: Annotated[float, si("dimensionless", ">0")] = 1.0
    delay: TimeNonNeg = 0.0


SensorSpec = Annotated[LoadcellSensor | EncoderSensor, Field(discriminator="type")]


def check_sensors(sensors: list[LoadcellSensor | EncoderSensor], span_names: list[str],
                  loadcell_spans: set[str], driven: set[str], roller_names: set[str],
                  fail: Callable[[str, str], NoReturn]) -> None:
    """``fail(key, problem)`` for the first sensor that names no loadcell span or driven
    roller, a name used twice, or two sensors on one signal. ``span_names``: the spans by
    name; ``loadcell_spans``: those with a tension reference; ``driven``: rollers with a
    drive; ``roller_names``: every roller."""
    names: set[str] = set()
    places: dict[str, str] = {}
    for s, sensor in enumerate(sensors):
        key = f"sensors[{s}]"
        if sensor.name in names:
            fail(f"{key}.name", f"sensor name {sensor.name!r} is used twice")
        names.add(sensor.name)
        if isinstance(sensor, LoadcellSensor):
            place = f"span {sensor.span}"
            if sensor.span not in span_names:
                fail(f"{key}.span", f"no span named {sensor.span!r}")
            if sensor.span not in loadcell_spans:
                fail(f"{key}.span", f"span {sensor.span!r} has no tension reference: no "
                     "controller reads a loadcell there")
        else:
            place = f"roller {sensor.roller}"
            if sensor.roller not in roller_names:
                fail(f"{key}.roller", f"no roller named {sensor.roller!r}")
            if sensor.roller not in driven:
                fail(f"{key}.roller", f"roller {sensor.roller!r} has no drive: no speed loop "
                     "reads an encoder there")
        if place in places:
            fail(key, f"{places[place]!r} already measures {place}")
        places[place] = sensor.name
