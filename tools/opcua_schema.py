"""The schema files of the OPC UA module (libs/opcua/schema), read once for both generators.

  status_codes.csv  name,value,description of every StatusCode (OPC 10000-4 §7.39)
  node_ids.csv      name,id,class of the namespace-0 NodeIds the stack uses (OPC 10000-6 Annex A)
  types.txt         enumerations and structures (see the header of that file)

tools/opcua_codegen.py makes the C++ types and tables of them, tools/opcua_ns0_gen.py the
namespace-0 node table; tools/test_opcua_schema.py tests this reader. Errors name the file and
line (SchemaError). Python 3 standard library only.
"""

import csv
import re

# Built-in types: C++ type, fewest encoded bytes, default member initializer.
BUILTINS = {
    "Boolean": ("bool", 1, " = false"),
    "SByte": ("std::int8_t", 1, " = 0"),
    "Byte": ("std::uint8_t", 1, " = 0"),
    "Int16": ("std::int16_t", 2, " = 0"),
    "UInt16": ("std::uint16_t", 2, " = 0"),
    "Int32": ("std::int32_t", 4, " = 0"),
    "UInt32": ("std::uint32_t", 4, " = 0"),
    "Int64": ("std::int64_t", 8, " = 0"),
    "UInt64": ("std::uint64_t", 8, " = 0"),
    "Float": ("float", 4, " = 0.0F"),
    "Double": ("double", 8, " = 0.0"),
    "String": ("String", 4, ""),
    "DateTime": ("DateTime", 8, ""),
    "Guid": ("Guid", 16, ""),
    "ByteString": ("ByteString", 4, ""),
    "XmlElement": ("XmlElement", 4, ""),
    "NodeId": ("NodeId", 2, ""),
    "ExpandedNodeId": ("ExpandedNodeId", 2, ""),
    "StatusCode": ("StatusCode", 4, ""),
    "QualifiedName": ("QualifiedName", 6, ""),
    "LocalizedText": ("LocalizedText", 1, ""),
    "ExtensionObject": ("ExtensionObject", 3, ""),
    "DataValue": ("DataValue", 1, ""),
    "Variant": ("Variant", 1, ""),
    "DiagnosticInfo": ("DiagnosticInfo", 1, ""),
}

CPP_KEYWORDS = {
    "alignas", "alignof", "and", "asm", "auto", "bool", "break", "case", "catch", "char", "class",
    "concept", "const", "constexpr", "continue", "default", "delete", "do", "double", "else", "enum",
    "explicit", "export", "extern", "false", "float", "for", "friend", "goto", "if", "inline", "int",
    "long", "mutable", "namespace", "new", "not", "operator", "or", "private", "protected", "public",
    "register", "requires", "return", "short", "signed", "sizeof", "static", "struct", "switch",
    "template", "this", "throw", "true", "try", "typedef", "typename", "union", "unsigned", "using",
    "virtual", "void", "volatile", "while", "xor",
}

IDENT = re.compile(r"^[A-Za-z_][A-Za-z0-9_]*$")


class SchemaError(Exception):
    pass


def fail(path, line, message):
    raise SchemaError(f"{path}:{line}: {message}")


def cpp_string(text):
    """A C++ string literal for text (ASCII-escaped)."""
    out = []
    for ch in text:
        if ch in '"\\':
            out.append("\\" + ch)
        elif 32 <= ord(ch) < 127:
            out.append(ch)
        else:
            out.extend(f"\\x{b:02x}" for b in ch.encode("utf-8"))
    return '"' + "".join(out) + '"'


def data_lines(path):
    """(line number, text) of the lines that are neither blank nor '#' comments."""
    with open(path, encoding="utf-8") as f:
        for number, line in enumerate(f, 1):
            if line.strip() and not line.lstrip().startswith("#"):
                yield number, line.rstrip("\n")


# ---- status_codes.csv ------------------------------------------------------------------------

def parse_status_codes(path):
    rows = list(data_lines(path))
    if not rows or rows[0][1] != "name,value,description":
        fail(path, rows[0][0] if rows else 1, "expected the header 'name,value,description'")
    codes, names, values = [], set(), set()
    for number, line in rows[1:]:
        fields = next(csv.reader([line]))
        if len(fields) != 3:
            fail(path, number, f"expected 3 columns, found {len(fields)}")
        name, value_text, description = fields
        if not IDENT.match(name):
            fail(path, number, f"'{name}' is not an identifier")
        try:
            value = int(value_text, 16)
        except ValueError:
            fail(path, number, f"'{value_text}' is not a hexadecimal value")
        if value & 0xFFFF or value > 0xFFFFFFFF:
            fail(path, number, f"{name}: the low 16 bits (info bits) must be zero")
        if name in names or value in values:
            fail(path, number, f"{name} ({value_text}) is defined twice")
        names.add(name)
        values.add(value)
        codes.append((name, value, description))
    return codes


# ---- node_ids.csv ----------------------------------------------------------------------------

NODE_CLASSES = ("DataType", "ReferenceType", "ObjectType", "VariableType", "Object", "Variable", "Method")


def parse_node_ids(path):
    rows = list(data_lines(path))
    if not rows or rows[0][1] != "name,id,class":
        fail(path, rows[0][0] if rows else 1, "expected the header 'name,id,class'")
    ids, by_name, by_id = [], {}, {}
    for number, line in rows[1:]:
        fields = line.split(",")
        if len(fields) != 3:
            fail(path, number, f"expected 3 columns, found {len(fields)}")
        name, id_text, node_class = (f.strip() for f in fields)
        if not IDENT.match(name):
            fail(path, number, f"'{name}' is not an identifier")
        if not id_text.isdigit() or int(id_text) > 0xFFFFFFFF:
            fail(path, number, f"'{id_text}' is not a UInt32")
        if node_class not in NODE_CLASSES:
            fail(path, number, f"unknown node class '{node_class}'")
        number_id = int(id_text)
        if name in by_name:
            fail(path, number, f"{name} is defined twice")
        if number_id in by_id:
            fail(path, number, f"i={number_id} is used by {by_id[number_id]} and {name}")
        by_name[name] = number_id
        by_id[number_id] = name
        ids.append((name, number_id, node_class))
    return ids, by_name


# ---- types.txt -------------------------------------------------------------------------------

class Enum:
    def __init__(self, name, comment, line):
        self.name, self.comment, self.line = name, comment, line
        self.values = []  # (name, value)


class Field:
    def __init__(self, name, type_name, array):
        self.name, self.type_name, self.array = name, type_name, array
        self.member = snake_case(name)


class Struct:
    def __init__(self, name, comment, line):
        self.name, self.comment, self.line = name, comment, line
        self.fields = []
        self.type_id = self.encoding_id = None
        self.min_size = 0

    @property
    def is_message(self):
        return bool(self.fields) and (self.fields[0].type_name, self.fields[0].name) in (
            ("RequestHeader", "requestHeader"), ("ResponseHeader", "responseHeader"))


def snake_case(name):
    s = re.sub(r"([a-z0-9])([A-Z])", r"\1_\2", name)
    s = re.sub(r"([A-Z]+)([A-Z][a-z])", r"\1_\2", s).lower()
    return s + "_" if s in CPP_KEYWORDS else s


def parse_types(path, node_ids):
    enums, structs, names = [], [], {}
    current = None
    for number, line in data_lines(path):
        text, _, comment = line.partition("#")
        comment = comment.strip()
        words = text.split()
        if not words:
            continue
        if not line.startswith((" ", "\t")):
            if len(words) != 2 or words[0] not in ("enum", "struct") or not IDENT.match(words[1]):
                fail(path, number, "expected 'enum <Name>' or 'struct <Name>'")
            kind, name = words
            if name in names or name in BUILTINS:
                fail(path, number, f"{name} is defined twice or shadows a built-in type")
            current = Enum(name, comment, number) if kind == "enum" else Struct(name, comment, number)
            (enums if kind == "enum" else structs).append(current)
            names[name] = current
            continue
        if current is None:
            fail(path, number, "indented line outside an enum or struct")
        if isinstance(current, Enum):
            m = re.match(r"^(\w+)\s*=\s*(-?\d+)$", text.strip())
            if not m:
                fail(path, number, "expected '<Name> = <value>'")
            value = int(m.group(2))
            if not -2**31 <= value < 2**31:
                fail(path, number, "enumeration values are Int32")
            if any(v[0] == m.group(1) for v in current.values):
                fail(path, number, f"{current.name}.{m.group(1)} is defined twice")
            current.values.append((m.group(1), value))
            continue
        if len(words) != 2 or not IDENT.match(words[0]):
            fail(path, number, "expected '<field> <Type>' or '<field> <Type>[]'")
        type_name, array = words[1], words[1].endswith("[]")
        if array:
            type_name = type_name[:-2]
        if type_name not in BUILTINS and not isinstance(names.get(type_name), (Enum, Struct)):
            fail(path, number, f"unknown type '{type_name}' (declare enums and structs before use)")
        if names.get(type_name) is current:
            fail(path, number, f"{current.name} cannot contain itself")
        if any(f.name == words[0] for f in current.fields):
            fail(path, number, f"{current.name}.{words[0]} is defined twice")
        current.fields.append(Field(words[0], type_name, array))
    for s in structs:
        for suffix, attr in (("", "type_id"), ("_Encoding_DefaultBinary", "encoding_id")):
            key = s.name + suffix
            if key not in node_ids:
                fail(path, s.line, f"{key} is missing from node_ids.csv")
            setattr(s, attr, key)
        # The XML encoding id is optional: only structures that travel in XML (NodeSet2 values)
        # need it.
        xml_key = s.name + "_Encoding_DefaultXml"
        s.xml_encoding_id = xml_key if xml_key in node_ids else None
        s.min_size = sum(4 if f.array else min_size_of(f.type_name, names) for f in s.fields)
    for e in enums:
        if not e.values:
            fail(path, e.line, f"enum {e.name} has no values")
    return enums, structs, names


def min_size_of(type_name, names):
    if type_name in BUILTINS:
        return BUILTINS[type_name][1]
    t = names[type_name]
    return 4 if isinstance(t, Enum) else t.min_size
