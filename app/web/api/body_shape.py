"""A request body's shape, bounded before anything validates it (docs/reference/limits.md, "Requests").

A body under the size limit can still cost seconds to validate: 1 MB of JSON holds 90,000 keys, and
pydantic reports each unknown one. So every JSON body is parsed once, off the event loop, and refused (413)
when it nests deeper, holds more keys or values, or longer strings, than any request of the API needs; only
then does FastAPI validate it. The bounds are far above the largest real request (a run's settings: about
60 values; rule text: one string of at most RULE_TEXT_MAX_LENGTH characters).
"""

from __future__ import annotations

import json
import sys
from dataclasses import dataclass

from soccer_lab.app.web.api.models import RULE_TEXT_MAX_LENGTH


class ShapeRefused(ValueError):
    """The body is not what the API reads: (status, one line saying why)."""

    def __init__(self, status: int, detail: str):
        super().__init__(detail)
        self.status = status
        self.detail = detail


@dataclass(frozen=True)
class BodyShape:
    max_depth: int = 16  # a run's settings nest 3 deep
    max_values: int = 2_000  # keys and values in all: a run's settings have about 60
    max_keys: int = 200  # keys in one object
    # characters in one string: over the longest field's (rule text), whose own limit then says which field
    max_string: int = 2 * RULE_TEXT_MAX_LENGTH
    max_key: int = 100  # characters in one key

    def check(self, body: bytes) -> None:
        """ShapeRefused (400 not UTF-8 or not JSON, 413 too large in shape) unless `body` is JSON of this shape."""
        try:
            text = body.decode("utf-8")
        except UnicodeDecodeError as exc:
            raise ShapeRefused(400, f"the body is not UTF-8 text (byte {exc.start} cannot be read)") from None
        try:
            # the hook sees each object as its pairs are read: a flood of keys stops at the first big object
            document = json.loads(text, object_pairs_hook=self._object)
        except json.JSONDecodeError as exc:
            raise ShapeRefused(400, f"malformed JSON: {exc.msg} at line {exc.lineno}, column {exc.colno}") from None
        except RecursionError:
            raise ShapeRefused(413, f"the body nests deeper than {self.max_depth} levels") from None
        except ShapeRefused:
            raise
        except ValueError:  # an integer past Python's digits limit (4,300): json.loads's only other refusal
            raise ShapeRefused(413, f"a number of the body has more than {sys.get_int_max_str_digits():,} "
                                    "digits") from None
        self._walk(document)

    def _object(self, pairs: list[tuple[str, object]]) -> dict[str, object]:
        if len(pairs) > self.max_keys:
            raise ShapeRefused(413, f"an object of the body has {len(pairs):,} keys; at most {self.max_keys:,}")
        return dict(pairs)

    def _walk(self, document: object) -> None:
        """Depth, values and string lengths, without recursion (a deep body cannot exhaust the stack)."""
        pending = [(document, 1)]
        values = 0
        while pending:
            node, depth = pending.pop()
            values += 1
            if values > self.max_values:
                raise ShapeRefused(413, f"the body holds more than {self.max_values:,} keys and values")
            if depth > self.max_depth:
                raise ShapeRefused(413, f"the body nests deeper than {self.max_depth} levels")
            if isinstance(node, str) and len(node) > self.max_string:
                raise ShapeRefused(413, f"a string of the body has {len(node):,} characters; at most "
                                        f"{self.max_string:,}")
            if isinstance(node, dict):
                for key, value in node.items():
                    if len(key) > self.max_key:
                        raise ShapeRefused(413, f"a key of the body has {len(key):,} characters; at most "
                                                f"{self.max_key}")
                    values += 1
                    pending.append((value, depth + 1))
            elif isinstance(node, list):
                pending.extend((item, depth + 1) for item in node)


BODY_SHAPE = BodyShape()
