"""`.ci/run` runs exactly the README's test command (the strict docs build, then the tests)."""
import re
from pathlib import Path

ROOT = Path(__file__).parents[1]


def test_ci_runs_the_readme_test_command():
    readme = (ROOT / "README.md").read_text(encoding="utf-8")
    section = readme.split("## Set-up: two commands", 1)[1].split("\n## ", 1)[0]
    commands = re.findall(r"```bash\n(.*?)\n```", section, flags=re.DOTALL)
    assert len(commands) == 2, commands
    ci = [line for line in (ROOT / ".ci" / "run").read_text().splitlines()
          if line.strip() and not line.startswith("#") and line not in ("set -euo pipefail",)
          and not line.startswith("cd ")]
    assert ci == [commands[1]]
    assert "mkdocs build --strict" in commands[1]
