"""Reading nfrc's output directories from the plotting scripts."""
import json
import os
import sys


def load_branch(directory, program):
    """DIR/branch.json as a dict; exits with a message naming `program` and the file if it
    cannot be read or parsed."""
    path = os.path.join(directory, "branch.json")
    try:
        with open(path) as handle:
            return json.load(handle)
    except OSError as error:
        sys.exit(f"{program}: cannot read {path}: {error.strerror}")
    except json.JSONDecodeError as error:
        sys.exit(f"{program}: {path} is not valid JSON: {error}")
