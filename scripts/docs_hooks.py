"""MkDocs hooks of the documentation site (``mkdocs.yml``: ``hooks``).

At every build, the scene-file reference page and the JSON schema are generated from
``radscene.scene.schema`` (:mod:`radscene.scene.reference`) and added to the site as
``scene_reference.md`` and ``scene.schema.json``; neither is kept in the repository.
"""

from __future__ import annotations

import json

from mkdocs.structure.files import File


def on_files(files, config):
    from radscene.scene.reference import scene_json_schema, scene_reference

    schema = json.dumps(scene_json_schema(), indent=2, ensure_ascii=False) + "\n"
    for name, content in (("scene_reference.md", scene_reference()),
                          ("scene.schema.json", schema)):
        existing = files.get_file_from_path(name)
        if existing is not None:
            files.remove(existing)
        files.append(File.generated(config, name, content=content))
    return files
