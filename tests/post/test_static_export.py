"""A static analysis exports like a run: one step whose tensions are the catenary's."""
import meshio
import numpy as np

import skmoor
from skmoor.post.export import export


def test_static_state_exports_with_catenary_tensions(tmp_path):
    model = skmoor.build(skmoor.paper_case())
    results = skmoor.static_results(model)
    xdmf, pvd = export(results, tmp_path)
    with meshio.xdmf.TimeSeriesReader(xdmf) as reader:
        points, _cells = reader.read_points_cells()
        assert reader.num_steps == 1
        _, _point_data, cell_data = reader.read_data(0)
    np.testing.assert_allclose(points, model.lines.points)
    # fairlead reactions of the FE state equal the analytic catenary's end tensions
    expected = [c.T_fairlead for c in model.catenaries]
    np.testing.assert_allclose(results.fairlead_tension[0], expected, rtol=1e-6)
    # element tensions at mid-points equal the catenary's there (equal unstretched elements)
    cat, n = model.catenaries[0], model.lines.lines[0].n_elements
    s_mid = (np.arange(n) + 0.5) * cat.L / n
    first_line = results.line_of_cell == 0
    np.testing.assert_allclose(cell_data["tension"][0][first_line], cat.tension(s_mid), rtol=1e-6)
    assert pvd.exists()
