"""Reading a YAML configuration file so that every error names the file (and, for bad YAML, the
line): the shared first step of the strict config loaders. Free of ROS."""
import yaml


def read_text(path, error_type, what):
    """The text of the file at `path`; error_type("<path>: cannot read <what>: <reason>") when it
    cannot be read."""
    try:
        with open(path, encoding="utf-8") as stream:
            return stream.read()
    except OSError as error:
        raise error_type("%s: cannot read %s: %s" % (path, what, error.strerror or error)) from None


def parse_yaml(text, source, error_type, label, loader=yaml.SafeLoader):
    """yaml.load(text, Loader=loader) (safe by default); error_type("<source>:<line>: <label>:
    <problem>") on bad YAML (without ":<line>" when YAML gives no position)."""
    try:
        return yaml.load(text, Loader=loader)
    except yaml.YAMLError as error:
        mark = getattr(error, "problem_mark", None)
        where = ":%d" % (mark.line + 1) if mark is not None else ""
        raise error_type("%s%s: %s: %s" % (source, where, label, getattr(error, "problem", None) or error)) from None
