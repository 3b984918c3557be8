"""Reading a URDF file into a Pinocchio model, with errors a user can act on.

The XML is checked here before Pinocchio sees it, because Pinocchio's parser (urdfdom)
reports a malformed file as "not a valid URDF model" and writes its real reason to stderr.
This pass names the joint or link, the value and the fix. Meshes are never loaded:
kinematics needs none.

How armik reads a URDF (docs/urdf.md says the same):

- Only regular files up to ``MAX_FILE_BYTES`` are read (never a device or a named pipe),
  and trees deeper than ``MAX_DEPTH`` links are refused: Pinocchio's parser recurses once
  per link and crashed the process at about 4000 links on an 8 MB stack (measured); so are
  files of more than ``MAX_MOVING`` moving joints (Pinocchio's data would take gigabytes).
- Joint axes follow ROS (Pinocchio, KDL, MoveIt): the unit vector along ``<axis xyz>``.
  A non-unit axis is normalised with an ``ArmikWarning`` (yourdfpy and pybullet would
  move a prismatic joint ``norm`` times as far); a zero, tiny (norm below
  ``AXIS_MIN_NORM``), non-finite or missing ``xyz`` is refused.
- ``<limit lower="0" upper="0">`` (or no lower/upper) means "not given": the joint is
  unlimited, with an ``ArmikWarning``. Other equal limits pin the joint at that value.
  The soft limits of a ``<safety_controller>`` bound the joint within ``<limit>``, as
  MoveIt reads them.
- Lengths above ``MAX_LENGTH`` m are refused: their arithmetic overflows in the solvers'
  restarts. Limits beyond ``MAX_LIMIT`` (rad or m; Gazebo models write +-1e16 for "free")
  mean no limit on that side, with an ``ArmikWarning``.
- A xacro file (``.xacro``, ``<xacro:`` tags outside comments, or ``${...}`` / ``$(...)``
  in a file that fails as plain URDF) is expanded with the ``xacro`` package when it is installed
  (``pip install armik[xacro]``); without it the error says how to expand it. ``<xacro:``
  tags without ``xmlns:xacro`` declared are not xacro (xacro refuses them; urdfdom ignores
  them): the file is read as plain URDF.
- XML that urdfdom's parser (TinyXML2) accepts and Python's refuses (comments nested or
  holding ``--``, undeclared prefixes) is read as urdfdom reads it, with an
  ``ArmikWarning`` naming the lines (``armik.model.urdf_lenient``).
"""

from __future__ import annotations

import logging
import os
import re
import stat
import tempfile
import threading
import warnings
import xml.etree.ElementTree as ET
from dataclasses import replace
from pathlib import Path

import pinocchio as pin

from armik.errors import URDFError
from armik.model.urdf_checks import MAX_DEPTH, MAX_MOVING, JointXML, URDFInfo, inspect
from armik.model.urdf_geometry import check_collisions
from armik.model.urdf_lenient import forgiving_parse

__all__ = [
    "MAX_DEPTH",
    "MAX_MOVING",
    "MAX_FILE_BYTES",
    "JointXML",
    "URDFInfo",
    "read_urdf",
    "read_urdf_string",
    "urdf_text",
]

log = logging.getLogger(__name__)

MAX_FILE_BYTES = 64 * 2**20  # the largest URDFs we know of (with inline meshes) are ~10 MB
# armik runs Pinocchio's recursive parser on a thread of its own with PARSER_STACK bytes of
# stack (room for about 16000 links) when the tree is deeper than SHALLOW_DEPTH (it
# crashed at 300 links on a 512 kB thread stack).
PARSER_STACK = 32 * 2**20
SHALLOW_DEPTH = 100  # up to here the caller's stack will do (200 kB; starting a thread: 1.5 ms)


def read_urdf(path: str | Path) -> tuple[pin.Model, URDFInfo]:
    """Parse ``path`` into a Pinocchio model. Raises ``URDFError`` naming the problem."""
    path = Path(path)
    text = _read_text(path)
    if _is_xacro(path, text):
        return _read_string(_expand_xacro(path, text), str(path))
    try:
        return _read_string(text, str(path))
    except URDFError as exc:
        # ${...} or $(...) left in a plain-looking file: xacro syntax. Generated URDFs keep
        # some in attributes nobody reads (and in comments), so only a file that fails as
        # plain URDF is expanded.
        if "${" not in text and "$(" not in text:
            raise
        try:
            import xacro  # noqa: F401
        except ImportError:
            raise URDFError(
                f"{exc} (the file holds ${{...}} or $(...): if it is a xacro file, expand "
                f"it with 'xacro {path} > robot.urdf' (ROS), or pip install xacro "
                "(armik[xacro]) and armik expands it itself)",
                path=str(path),
            ) from None
    return _read_string(_expand_xacro(path, text), str(path))


def urdf_text(path: str | Path) -> str:
    """The XML of the URDF at ``path``, a xacro file expanded: the text its visuals are read
    from (``armik.view``). Raises ``URDFError`` as ``read_urdf`` does."""
    path = Path(path)
    text = _read_text(path)
    if _is_xacro(path, text):
        return _expand_xacro(path, text)
    try:
        ET.fromstring(text)
    except ET.ParseError as exc:  # read as urdfdom reads it (warned when the arm loaded)
        root, _ = forgiving_parse(text, str(path), exc, warn=False)
        return ET.tostring(root, encoding="unicode")
    return text


def read_urdf_string(text: str, where: str = "<string>") -> tuple[pin.Model, URDFInfo]:
    """Check the URDF text (plain URDF: a xacro text is refused, naming the way to expand
    it), normalise its axes, and build the Pinocchio model."""
    expand = (
        "load_string reads plain URDF: expand it with 'xacro robot.urdf.xacro > robot.urdf' "
        "(ROS), or save it as a .xacro file and armik.load that file (pip install xacro)"
    )
    if "<xacro:" in text and _is_xacro(Path("text"), text):  # tags urdfdom would skip
        raise URDFError(f"URDF text {where!r} is xacro (<xacro:...> tags): {expand}", path=where)
    try:
        return _read_string(text, where)
    except URDFError as exc:
        live = _COMMENT.sub("", text)
        if "${" not in live and "$(" not in live:
            raise
        message = f"{exc} (the text holds xacro's ${{...}} or $(...): {expand})"
        raise URDFError(message, path=exc.path) from None


def _read_string(text: str, where: str) -> tuple[pin.Model, URDFInfo]:
    """Check the URDF text, normalise its axes, and build the Pinocchio model."""
    if not text.strip():
        raise URDFError(f"URDF file {where!r} is empty", path=where)
    forgiven: tuple[str, ...] = ()
    lenient = False
    try:
        root = ET.fromstring(text)
    except ET.ParseError as exc:  # only then: well-formed files pay nothing for this
        _refuse_a_path(text, where)
        root, forgiven = forgiving_parse(text, where, exc)
        lenient = True  # Pinocchio gets the text as armik read it
    namespaced = root.tag.startswith("{")
    if namespaced:  # <robot xmlns="...">: urdfdom ignores the namespace, so does armik
        for elem in root.iter():
            if isinstance(elem.tag, str) and elem.tag.startswith("{"):
                elem.tag = elem.tag.split("}", 1)[1]
    info, changed = inspect(root, where)
    check_collisions(root, where)
    if changed or namespaced or lenient:
        text = ET.tostring(root, encoding="unicode")
    model = _build(text, where, own_stack=info.depth > SHALLOW_DEPTH)
    # the text: collision geometry is read from it
    return model, replace(info, text=text, notes=forgiven + info.notes)


def _refuse_a_path(text: str, where: str) -> None:
    """A ``URDFError`` when the text that is not XML is a file's path (it names a file,
    or ends in .urdf, .xacro or .xml, with no '<'): ``armik.load`` reads files."""
    given = text.strip()
    if "<" in given or "\n" in given or len(given) > 4096:
        return
    try:
        names_a_file = Path(given).expanduser().is_file()
    except (OSError, ValueError):  # a NUL byte, a name too long
        names_a_file = False
    if names_a_file or given.lower().endswith((".urdf", ".xacro", ".xml")):
        raise URDFError(
            f"URDF text {where!r} is {given!r}, a file's path, not the URDF's XML: read "
            f"the file with armik.load({given!r}) (load_string takes the XML itself)",
            path=where,
        )


# -- the file ------------------------------------------------------------------------------


def _read_text(path: Path) -> str:
    where = str(path)
    try:
        st = os.stat(path)
    except FileNotFoundError:
        raise URDFError(f"URDF file {where!r} does not exist: check the path", path=where) from None
    except OSError as exc:
        raise URDFError(f"cannot read URDF file {where!r}: {exc.strerror}", path=where) from None
    if stat.S_ISDIR(st.st_mode):
        raise URDFError(f"{where!r} is a directory: pass the .urdf file inside it", path=where)
    if not stat.S_ISREG(st.st_mode):
        raise URDFError(
            f"{where!r} is not a regular file (a device, pipe or socket): armik reads URDF "
            "files only; save the description to a file first",
            path=where,
        )
    if st.st_size > MAX_FILE_BYTES:
        raise URDFError(
            f"URDF file {where!r} is {st.st_size / 2**20:.0f} MB, above the "
            f"{MAX_FILE_BYTES // 2**20} MB armik reads: is it really a URDF?",
            path=where,
        )
    try:
        with open(path, "rb") as fh:
            data = fh.read(MAX_FILE_BYTES + 1)
    except OSError as exc:
        raise URDFError(f"cannot read URDF file {where!r}: {exc.strerror}", path=where) from None
    if len(data) > MAX_FILE_BYTES:  # grew while we looked
        raise URDFError(f"URDF file {where!r} is larger than {MAX_FILE_BYTES} bytes", path=where)
    return data.decode("utf-8", errors="replace")


def _is_xacro(path: Path, text: str) -> bool:
    """Whether the file is xacro to expand: ``<xacro:`` tags outside comments with the
    prefix declared. Undeclared, xacro itself refuses them and urdfdom ignores them; in
    comments (example-robot-data's TALOS, generated by xacro, keeps some) nobody reads
    them: such files are plain URDF."""
    if path.suffix.lower() == ".xacro":
        return True
    if "<xacro:" not in text:
        return False
    live = _COMMENT.sub("", text)  # as TinyXML2 delimits comments: to the first -->
    return "<xacro:" in live and _XACRO_DECLARED.search(live) is not None


_XACRO_DECLARED = re.compile(r"xmlns:xacro\s*=")
_COMMENT = re.compile(r"<!--.*?-->", re.S)


def _expand_xacro(path: Path, text: str) -> str:
    where = str(path)
    command = f"xacro {where} > robot.urdf"
    try:
        import xacro
    except ImportError:
        raise URDFError(
            f"{where!r} is a xacro file (macros and ${{...}} expressions), not plain URDF: "
            f"expand it with {command!r} (ROS), or pip install xacro (armik[xacro]) and armik "
            "expands it itself",
            path=where,
        ) from None
    try:
        with warnings.catch_warnings():
            warnings.simplefilter("ignore")
            doc = xacro.process_file(where)
    except (Exception, SystemExit) as exc:  # xacro raises its own types, some exit
        text = str(exc).strip()
        message = text.splitlines()[0].strip() if text else type(exc).__name__
        raise URDFError(
            f"{where!r} is a xacro file and the xacro package could not expand it "
            f"({message}): expand it with {command!r} in its ROS workspace and load the result",
            path=where,
        ) from None
    log.info("expanded xacro file %s", where)
    return doc.toxml()


# -- Pinocchio ----------------------------------------------------------------------------

_STACK_LOCK = threading.Lock()
_STDERR_LOCK = threading.Lock()


def _build(text: str, where: str, own_stack: bool) -> pin.Model:
    """``pin.buildModelFromXML`` with urdfdom's stderr kept; on a thread with a large stack
    when ``own_stack`` (deep trees)."""
    out: dict[str, object] = {}

    def work() -> None:
        try:
            out["model"], out["stderr"] = _with_stderr(pin.buildModelFromXML, text)
        except _Failed as exc:
            out["error"], out["stderr"] = exc.error, exc.stderr

    if own_stack:
        with _STACK_LOCK:
            old = threading.stack_size(PARSER_STACK)
            try:
                thread = threading.Thread(target=work, name="armik-urdf-parser")
                thread.start()
            finally:
                threading.stack_size(old)
        thread.join()
    else:
        work()
    stderr = str(out.get("stderr") or "").strip()
    if "model" in out:
        if stderr:
            log.info("Pinocchio's URDF parser said: %s", stderr)
        return out["model"]  # type: ignore[return-value]
    reasons = [
        line.strip().removeprefix("Error:").strip()
        for line in stderr.splitlines()
        if line.strip() and not line.strip().startswith("at line")
    ]
    detail = "; ".join(reasons) if reasons else str(out.get("error"))
    raise URDFError(f"Pinocchio could not build a model from {where!r}: {detail}", path=where)


class _Failed(Exception):
    def __init__(self, error: BaseException, stderr: str) -> None:
        self.error, self.stderr = error, stderr


def _with_stderr(func, *args):
    """Run ``func`` with file descriptor 2 sent to a temporary file; returns (value, text).
    urdfdom writes its reasons there from C++, out of Python's reach otherwise."""
    with _STDERR_LOCK, tempfile.TemporaryFile(mode="w+b") as tmp:
        try:
            saved = os.dup(2)
        except OSError:  # no fd 2 (some embedded interpreters): run as is
            try:
                return func(*args), ""
            except Exception as exc:  # Pinocchio raises bare RuntimeError/ValueError
                raise _Failed(exc, "") from None
        try:
            os.dup2(tmp.fileno(), 2)
            try:
                value = func(*args)
                error = None
            except Exception as exc:
                value, error = None, exc
        finally:
            os.dup2(saved, 2)
            os.close(saved)
        tmp.seek(0)
        text = tmp.read(64 * 1024).decode("utf-8", errors="replace")
    if error is not None:
        raise _Failed(error, text)
    return value, text
