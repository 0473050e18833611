/* placeholder */ typedef int placeholder_diff;
