/* placeholder */ typedef int placeholder_image;
