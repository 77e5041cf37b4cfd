# Rewrites the code's citations of the old method document ("METHOD §n") to docs/method/.
# Usage: sed -i -f scripts/cite-method.sed $(grep -rl "METHOD §" src include apps python tests bench README.md docs/*.md)
# The mapping is the table in docs/method/README.md. Ranges first, then §10 before §1 (\b keeps
# "§1" from matching "§10"). Lists of sections come first of all.
s|METHOD §1 step 5, §4|docs/method/10-compensation.md, 02-frames.md §7|g
s|METHOD §1, §3|docs/method/01-overview.md, 03-error-model.md|g
s|METHOD §2, §3, §10|docs/method/02-frames.md, 03-error-model.md, 11-published-results.md|g
s|METHOD §3, §5|docs/method/03-error-model.md, 04-identification.md|g
s|METHOD §5, §7|docs/method/04-identification.md, 06-instruments.md|g
s|METHOD §8 procedure, §10 LR Mate 200iC|docs/method/08-world-frame.md §3, 11-published-results.md (LR Mate 200iC)|g
s|METHOD §2–§3|docs/method/02-frames.md, 03-error-model.md|g
s|METHOD §2–§4|docs/method/02-frames.md, 03-error-model.md|g
s|METHOD §5–§6|docs/method/04-identification.md, 05-observability.md|g
s|METHOD §10\b|docs/method/11-published-results.md|g
s|METHOD §1 step 5|docs/method/10-compensation.md|g
s|METHOD §1\b|docs/method/01-overview.md|g
s|METHOD §2\b|docs/method/02-frames.md|g
s|METHOD §3\b|docs/method/03-error-model.md|g
s|METHOD §4\b|docs/method/02-frames.md §7|g
s|METHOD §5\b|docs/method/04-identification.md|g
s|METHOD §6\b|docs/method/05-observability.md|g
s|METHOD §7\b|docs/method/06-instruments.md|g
s|METHOD §8\b|docs/method/07-hexapod.md|g
s|METHOD §9\b|docs/method/09-validation.md|g
