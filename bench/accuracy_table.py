#!/usr/bin/env python3
"""The "Accuracy and time" table of docs/user-guide.md from ssgi_sweep CSVs: for each scene and
variant (a label per CSV), the presets' frame time, display RMSE against the reference, and the
display RMSE and mean test/reference ratio in each region (lit, in shadow, reflective, background).

    python3 bench/accuracy_table.py default:paper=sweep_default_off.csv default:sky=sweep_default.csv ...

Each argument is SCENE:VARIANT=FILE. Python 3 standard library only.
"""
import csv
import sys

REGIONS = [("lit", "lit"), ("shadow", "in shadow"), ("reflective", "reflective"), ("background", "background")]


def cell(row, region):
    rmse, ratio = row.get("rmse_display_" + region, ""), row.get("ratio_" + region, "")
    if not rmse:
        return ""
    try:
        ratio_text = "%.2f" % float(ratio)
    except ValueError:
        ratio_text = "-"
    return "%.4f (%s)" % (float(rmse), ratio_text)


def main(arguments):
    if not arguments or any("=" not in a or ":" not in a.split("=")[0] for a in arguments):
        sys.exit(__doc__)
    header = ["scene", "variant", "preset", "frame (ms)", "display RMSE"] + [title for _, title in REGIONS]
    print("| " + " | ".join(header) + " |")
    print("|" + "---|" * len(header))
    for argument in arguments:
        label, path = argument.split("=", 1)
        scene, variant = label.split(":", 1)
        with open(path, newline="") as f:
            for row in csv.DictReader(f):
                if row["knob"] not in ("preset",):
                    continue
                cells = [scene, variant, row["value"], "%.1f" % float(row["frame_ms"]),
                         "%.4f" % float(row["rmse_display"])] + [cell(row, region) for region, _ in REGIONS]
                print("| " + " | ".join(cells) + " |")


if __name__ == "__main__":
    main(sys.argv[1:])
