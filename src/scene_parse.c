/* placeholder */ typedef int placeholder_scene_parse;
