#!/usr/bin/env python3
"""Tests of tools/opcua_schema.py, the reader of libs/opcua/schema both generators use: what it
takes from each file, and that every mistake in a schema file is an error naming file and line.

    python3 -m unittest discover -s tools -p 'test_*.py'   (CTest: opcua_schema_reader)
"""
import os
import sys
import tempfile
import textwrap
import unittest

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import opcua_schema as schema  # noqa: E402

NODE_IDS = """\
name,id,class
# a comment line and a blank line are skipped

Point,1001,DataType
Point_Encoding_DefaultBinary,1002,Object
Box,1003,DataType
Box_Encoding_DefaultBinary,1004,Object
Box_Encoding_DefaultXml,1005,Object
"""


class SchemaFiles(unittest.TestCase):
    def setUp(self):
        self.dir = tempfile.TemporaryDirectory()
        self.addCleanup(self.dir.cleanup)

    def file(self, name, text):
        path = os.path.join(self.dir.name, name)
        with open(path, "w", encoding="utf-8") as f:
            f.write(textwrap.dedent(text))
        return path

    def node_ids(self, text=NODE_IDS):
        return schema.parse_node_ids(self.file("node_ids.csv", text))

    def assert_error(self, parse, path_name, line, words):
        with self.assertRaises(schema.SchemaError) as caught:
            parse()
        message = str(caught.exception)
        self.assertIn(f"{path_name}:{line}:", message)
        self.assertIn(words, message)


class StatusCodes(SchemaFiles):
    def test_reads_names_values_and_quoted_descriptions(self):
        path = self.file("status_codes.csv", """\
            name,value,description
            Good,0x00000000,"The operation succeeded."
            BadDecodingError,0x80070000,"Decoding halted, because of invalid data."
            """)
        self.assertEqual(schema.parse_status_codes(path), [
            ("Good", 0, "The operation succeeded."),
            ("BadDecodingError", 0x80070000, "Decoding halted, because of invalid data."),
        ])

    def test_mistakes_name_the_line(self):
        cases = [
            ("name,value\nGood,0x0\n", 1, "expected the header"),
            ("name,value,description\nGood,0x0\n", 2, "expected 3 columns"),
            ("name,value,description\nBad-Thing,0x80000000,x\n", 2, "not an identifier"),
            ("name,value,description\nBadThing,0x8zz,x\n", 2, "not a hexadecimal value"),
            ("name,value,description\nBadThing,0x80000001,x\n", 2, "info bits"),
            ("name,value,description\nA,0x80010000,x\nB,0x80010000,y\n", 3, "defined twice"),
        ]
        for text, line, words in cases:
            with self.subTest(words=words):
                path = self.file("status_codes.csv", text)
                self.assert_error(lambda: schema.parse_status_codes(path), "status_codes.csv", line, words)


class NodeIds(SchemaFiles):
    def test_reads_ids_by_name(self):
        ids, by_name = self.node_ids()
        self.assertEqual(ids[0], ("Point", 1001, "DataType"))
        self.assertEqual(by_name["Box_Encoding_DefaultXml"], 1005)
        self.assertEqual(len(ids), 5)

    def test_mistakes_name_the_line(self):
        cases = [
            ("name,id,class\nPoint,x,DataType\n", 2, "not a UInt32"),
            ("name,id,class\nPoint,1,Thing\n", 2, "unknown node class"),
            ("name,id,class\nPoint,1,DataType\nPoint,2,DataType\n", 3, "defined twice"),
            ("name,id,class\nA,1,DataType\nB,1,DataType\n", 3, "used by A and B"),
        ]
        for text, line, words in cases:
            with self.subTest(words=words):
                self.assert_error(lambda: self.node_ids(text), "node_ids.csv", line, words)


class Types(SchemaFiles):
    TYPES = """\
        enum Color  # a comment
          Red = 0
          Green = 1
        struct Point
          x Double
          y Double
        struct Box
          corners Point[]
          color Color
          label String
        """

    def parse(self, text):
        _, by_name = self.node_ids()
        return schema.parse_types(self.file("types.txt", text), by_name)

    def test_reads_enums_structs_fields_and_encodings(self):
        enums, structs, names = self.parse(self.TYPES)
        self.assertEqual([(e.name, e.values) for e in enums], [("Color", [("Red", 0), ("Green", 1)])])
        box = names["Box"]
        self.assertEqual([(f.name, f.type_name, f.array) for f in box.fields],
                         [("corners", "Point", True), ("color", "Color", False), ("label", "String", False)])
        self.assertEqual(box.encoding_id, "Box_Encoding_DefaultBinary")
        self.assertEqual(box.xml_encoding_id, "Box_Encoding_DefaultXml")
        self.assertIsNone(names["Point"].xml_encoding_id)
        self.assertEqual(names["Point"].min_size, 16)
        self.assertEqual(box.min_size, 4 + 4 + 4)  # array length, Int32 enum, String length

    def test_mistakes_name_the_line(self):
        cases = [
            ("thing Point\n", 1, "expected 'enum <Name>' or 'struct <Name>'"),
            ("# a field first\n  x Double\n", 2, "outside an enum or struct"),
            ("enum Color\n  Red\n", 2, "expected '<Name> = <value>'"),
            ("enum Color\n  Red = 4294967296\n", 2, "Int32"),
            ("enum Color\n  Red = 0\n  Red = 1\n", 3, "defined twice"),
            ("enum Color\n", 1, "has no values"),
            ("struct Point\n  x Vector\n", 2, "unknown type 'Vector'"),
            ("struct Point\n  p Point\n", 2, "cannot contain itself"),
            ("struct Point\n  x Double\n  x Double\n", 3, "defined twice"),
            ("struct Double\n", 1, "shadows a built-in type"),
            ("struct Circle\n  r Double\n", 1, "Circle is missing from node_ids.csv"),
        ]
        for text, line, words in cases:
            with self.subTest(words=words):
                self.assert_error(lambda: self.parse(text), "types.txt", line, words)


class Helpers(unittest.TestCase):
    def test_cpp_string_escapes_quotes_and_non_ascii(self):
        self.assertEqual(schema.cpp_string('say "hi" \\ ok'), '"say \\"hi\\" \\\\ ok"')
        self.assertEqual(schema.cpp_string("§"), '"\\xc2\\xa7"')

    def test_snake_case_avoids_cpp_keywords(self):
        self.assertEqual(schema.snake_case("requestHeader"), "request_header")
        self.assertEqual(schema.snake_case("NodeID"), "node_id")
        self.assertEqual(schema.snake_case("Default"), "default_")


if __name__ == "__main__":
    unittest.main()
