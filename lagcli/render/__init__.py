"""What every output shares: turning values into text, and text into files.

    templates.py     the one strict Jinja environment (templates/ as lagcli.templates)
    escape.py        the one escaping function per output grammar (Jinja filters)
    tidy.py          exact tidying of small expressions for display
    spec_printer.py  sympy -> the spec's own expression language
    output.py        where -o / --plot write (atomic files, streams); interrupts.py: signals

(templates/ and specs/ are found by lagcli/runtime/package_data.py, below the spec reader.)
"""
