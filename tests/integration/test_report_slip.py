"""The report shows web slip for rollers with a traction contact (issue 6)."""

from __future__ import annotations

import webline
from webline.report.writer import write_report


def test_report_has_slip_figure(tmp_path, hswl):
    data = hswl.spec.model_dump(exclude_none=True)
    data["rollers"][2]["wrap"] = "180 deg"
    data["rollers"][2]["contact"] = {"type": "traction", "friction": 0.003, "viscous": 2000.0}
    data["disturbances"] = [{"type": "speed_ripple", "roller": "rewind",
                             "amplitude": "20 ft/min", "frequency": "2 Hz"}]
    result = webline.simulate(webline.load_line(data), 2.0)
    assert result.slipping[:, 2].any()
    report = write_report(result, tmp_path)
    assert (tmp_path / "figures" / "slip.png").stat().st_size > 1000
    assert "Web slip over the rollers" in report.report.read_text(encoding="utf-8")
    # and an adhered line has no slip figure
    plain = write_report(webline.simulate(hswl, 0.5), tmp_path / "plain")
    assert "Web slip over the rollers" not in plain.report.read_text(encoding="utf-8")
