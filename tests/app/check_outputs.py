#!/usr/bin/env python3
"""Checks a dsdem output directory left by a killed or stopped run: every .vtu/.pvd is
well-formed XML, every .json parses, history.csv has only complete lines with one value
per header column. Prints what it checked; exit 1 with the reason on the first defect."""
import json, os, sys
import xml.etree.ElementTree as ET

root = sys.argv[1]
vtus = []
counts = {"vtu": 0, "pvd": 0, "json": 0, "csv_rows": 0}
for dirpath, _, files in os.walk(root):
    for f in files:
        p = os.path.join(dirpath, f)
        ext = f.rsplit(".", 1)[-1]
        try:
            if ext == "vtu":
                # Raw appended binary data: not plain XML. Complete means: ends with the
                # closing tag, and the XML header before the data parses; a sample of
                # frames is read in full with meshio.
                data = open(p, "rb").read()
                assert data.rstrip().endswith(b"</VTKFile>"), "does not end with </VTKFile>"
                head = data.split(b"<AppendedData")[0] + b"</VTKFile>" if b"<AppendedData" in data else data
                assert ET.fromstring(head).tag == "VTKFile", "root element is not VTKFile"
                vtus.append(p)
                counts[ext] += 1
            elif ext == "pvd":
                t = ET.parse(p).getroot()
                assert t.tag == "VTKFile", "root element is not VTKFile"
                if ext == "pvd":
                    for ds in t.iter("DataSet"):
                        assert os.path.exists(os.path.join(os.path.dirname(p), ds.get("file"))), \
                            "refers to missing " + ds.get("file")
                counts[ext] += 1
            elif ext == "json":
                json.load(open(p))
                counts["json"] += 1
            elif f == "history.csv":
                data = open(p).read()
                assert data.endswith("\n"), "last line incomplete"
                lines = data.splitlines()
                n = lines[0].count(",")
                for i, line in enumerate(lines[1:], 2):
                    assert line.count(",") == n, "line %d has %d fields, header %d" % (i, line.count(",") + 1, n + 1)
                    [float(x) for x in line.split(",")]
                counts["csv_rows"] = len(lines) - 1
        except Exception as e:  # noqa: BLE001
            print("DEFECT %s: %s" % (p, e))
            sys.exit(1)
try:
    import meshio
    sample = sorted(vtus)
    sample = sample[:5] + sample[-5:] if len(sample) > 10 else sample
    for p in sample:
        meshio.read(p)
except ImportError:
    pass
except Exception as e:  # noqa: BLE001
    print("DEFECT %s: %s" % (p, e))
    sys.exit(1)
print("OK vtu=%(vtu)d pvd=%(pvd)d json=%(json)d history_rows=%(csv_rows)d" % counts)
