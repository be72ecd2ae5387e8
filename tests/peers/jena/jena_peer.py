"""Apache Jena as a reference peer: classpath, the Debian packaging fix and the compiled driver.

Debian's jena-core (libapache-jena-java 4.5) relocates its shaded Xerces to the package
`xerces` but keeps the message resources under org/apache/jena/ext/xerces/..., so the first
XSD datatype Jena builds fails with "internal error" while looking up a message. The resources
are copied from the installed jar to where the relocated classes look for them
(xerces/impl/msg/*.properties, xerces/impl/xpath/regex/message*.properties).

    python3 tests/peers/jena/jena_peer.py build DIR    # prints the classpath to run JenaReason
"""
import os
import shutil
import subprocess
import sys
import zipfile

JAVA_DIR = "/usr/share/java"
# jena-arq (RIOT parsers) and what it loads at start-up (Debian package dependencies).
JARS = ["jena-core", "jena-arq", "jena-base", "jena-iri", "thrift", "slf4j-api", "slf4j-nop",
        "commons-lang3", "commons-io", "commons-codec", "commons-compress", "commons-csv", "commons-cli",
        "dexx.collection", "gson", "guava", "httpclient", "httpcore", "jackson-core", "jackson-databind",
        "jackson-annotations", "jsonld-java", "protobuf", "titanium-json-ld", "jakarta.json-api"]
HERE = os.path.dirname(os.path.abspath(__file__))


def missing():
    """What is missing to run the peer, or None."""
    for tool in ("java", "javac"):
        if shutil.which(tool) is None:
            return f"{tool} is not installed (scripts/setup installs default-jdk-headless)"
    for jar in ("jena-core", "jena-arq"):
        if not os.path.exists(os.path.join(JAVA_DIR, jar + ".jar")):
            return f"{jar}.jar is not installed (scripts/setup installs libapache-jena-java)"
    return None


def restore_xerces_messages(jena_core, dest):
    with zipfile.ZipFile(jena_core) as jar:
        for name in jar.namelist():
            prefix = "org/apache/jena/ext/xerces/"
            if name.startswith(prefix) and name.endswith(".properties"):
                target = os.path.join(dest, "xerces", name[len(prefix):])
                os.makedirs(os.path.dirname(target), exist_ok=True)
                with jar.open(name) as src, open(target, "wb") as out:
                    out.write(src.read())


def build(workdir):
    """Compiles JenaReason.java into workdir; returns the classpath string to run it."""
    os.makedirs(workdir, exist_ok=True)
    jars = [os.path.join(JAVA_DIR, j + ".jar") for j in JARS if os.path.exists(os.path.join(JAVA_DIR, j + ".jar"))]
    resources = os.path.join(workdir, "resources")
    restore_xerces_messages(os.path.join(JAVA_DIR, "jena-core.jar"), resources)
    classes = os.path.join(workdir, "classes")
    subprocess.run(["javac", "-nowarn", "-d", classes, "-cp", ":".join(jars), os.path.join(HERE, "JenaReason.java")],
                   check=True)
    return ":".join(jars + [resources, classes])


if __name__ == "__main__":
    if len(sys.argv) != 3 or sys.argv[1] != "build":
        sys.exit("usage: jena_peer.py build DIR")
    why = missing()
    if why:
        sys.exit(why)
    print(build(sys.argv[2]))
