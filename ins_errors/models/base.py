"""Old home of the model building blocks; they live in :mod:`ins_errors.modeling` now.

Kept as an alias so code written against ``ins_errors.models.base`` keeps working;
new code imports from :mod:`ins_errors.modeling`.
"""

from ins_errors.modeling import *  # noqa: F403
from ins_errors.modeling import __all__  # noqa: F401
